"""The deck: TOML in, a validated Deck out (load.py). Every field is declared once in schema.py
with its unit, default and rule (fields.py: the rules and the one-line errors; choices.py: the
closest name suggested; practice.py: the warnings of values far outside building practice);
[building] and [foundation] are built in building.py, [ground_motion] in motion.py (a suite:
suite.py), [criteria] in criteria.py, and `--set` overrides in overrides.py."""
