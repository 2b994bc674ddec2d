"""Analysis engines: simplified (response spectrum), exact and approximate (response history),
by name in registry.py."""
