"""The loops of the response spectra, compiled (C: _spectra.c, built at install) or their numpy
twin (spectra_numpy.py), as upliftcli.runtime.backend chooses: the exact
Nigam-Jennings step, the bound that finds the steps where a peak can lie between samples, and
the exact turning points there (see spectra.py for the method). Each loop runs over many
oscillators at once.

spectrum_kernel(acc, dt, omegas, xis, nsubs, chunk_starts, free_vibration, out_u, out_at):
    peak |u| [m] and |absolute acceleration| [m/s^2] of the oscillators (omegas [rad/s] > 0,
    damping ratios xis) into out_u, out_at, chunk by chunk: [chunk_starts[c], chunk_starts[c+1])
    share the sub-step count nsubs (int64) of their first oscillator; one thread (the sweeps
    parallelise over processes).
history_kernel(acc, dt, w, xi, u_out, v_out):
    relative displacement and velocity at the samples of acc, zero initial conditions.

Arrays are C-contiguous float64 (int64 where said), the outputs written in place.
"""

from __future__ import annotations

from ..runtime import backend


def _loops():
    return backend.loops(f"{__package__}._spectra", f"{__package__}.spectra_numpy")


def spectrum_kernel(acc, dt, omegas, xis, nsubs, chunk_starts, free_vibration, out_u, out_at) -> None:
    _loops().spectrum_kernel(acc, dt, omegas, xis, nsubs, chunk_starts, free_vibration, out_u, out_at)


def history_kernel(acc, dt, w, xi, u_out, v_out) -> None:
    _loops().history_kernel(acc, dt, w, xi, u_out, v_out)
