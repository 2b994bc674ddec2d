"""Where a result came from: the provenance record of every result file (record.py), its input
files with their SHA-256 (files.py) and the derived model and engine options (model.py)."""
