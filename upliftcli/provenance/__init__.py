"""Where a result came from: the provenance record of every result file (record.py), its input
files with their SHA-256 (files.py), the derived model and engine options (model.py), and the
plain, JSON-ready values and the text of their numbers every result file uses (values.py).
Imports go one way: values <- model, files <- record."""
