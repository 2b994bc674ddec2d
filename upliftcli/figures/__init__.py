"""Figure data: pure functions of results (engines/result.AnalysisResult), modes, spectra and
suites returning spec.FigureSpec (arrays and labels, no matplotlib), drawn by upliftcli.figures.draw
(the layout: layout.py; each panel: panels.py).

    analysis.profile_figure(results, criteria)    story profiles of peak response
    modes.mode_shape_figure(system)               fixed-base mode shapes, T_n, m_n*/m_t
    histories.history_figure(results)             Fig. 5 style histories (contact state shaded)
    histories.moment_rotation_figure(results)     M_b against theta, +-M_c
    histories.energy_figure(results)              energy balance as bars
    spectra.record_spectrum_figure(spectrum)      S_d, S_v, S_a of a record
    spectra.suite_figure(suite)                   suite spectra: records thin, statistic thick, target dashed

The sweep figures (paper Figs. 3, 4, 6-10) are upliftcli.sweep.figures.
"""
