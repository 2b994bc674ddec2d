"""The structural model: building and its fixed-base modes, foundations, the whole system."""
