"""What every method of the core shares: its result's base, its errors, its checks and the tables it is told in.

:mod:`.result` (the base every result class derives from: ``CalibrationResult``, the still-readings and per-sensor
results, the registry each class enters by its type, the page's facts, the figures), :mod:`.errors`,
:mod:`.validation` (shapes, finiteness, reference magnitudes), :mod:`.gates` (the quality gates a fit chooses its
thresholds for), :mod:`.plausible` (the physical limits every result is held to), :mod:`.uncertainty` (intervals from
a covariance), :mod:`.correction` (``f = M (m − o)``, every model's correction), :mod:`.norm_metrics` (the norm errors
of still readings), :mod:`.gravity`, :mod:`.orientations` (which axis points up), :mod:`.rotations` (the flight
controllers' sensor rotations), :mod:`.capture` (the wizard's capture checks, for the still poses and the cube),
:mod:`.headlines` and :mod:`.angles` (the words and angles a figure is told in), :mod:`.chi2` (χ² quantiles) and
:mod:`.cores` (the cores the core's threads are counted from). Nothing here imports a method.
"""
