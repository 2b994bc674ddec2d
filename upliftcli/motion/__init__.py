"""Ground motions: records, response spectra, design spectra."""
