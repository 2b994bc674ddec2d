"""What runs beneath the tool and knows nothing of structures: atomic writes (atomic.py), locks
(locks.py), worker processes and stop signals (process.py), the differences between systems
(portable.py), the loops in use, compiled or numpy (backend.py), the installed versions
(installed.py) and the documented limits on the size of a run (limits.py)."""
