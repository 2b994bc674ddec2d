"""Analysis: a deck in, results out, through the engine registry (run.py; a record suite:
suite.py), and the checks of the simplified engine against the exact one (accuracy.py on the
deck's record or suite, suite_check.py on the suite generated for a design spectrum). Knows
nothing of the terminal or files."""
