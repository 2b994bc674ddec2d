"""Sweeps: a deck over ranges of its fields (plan, worker, executors, store, table, figures)."""
