"""The calculation report (`uplift report`, docs/report.md): build.py gathers a run's inputs,
model, results, checks and figures into a Report (document.py: sections of text, tables and
figures, no HTML); html.py writes it as one self-contained HTML file. inputs.py, method.py,
results.py, checks.py (accuracy, warnings, criteria) and provenance/record.py build the sections."""
