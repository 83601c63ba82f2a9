"""A stored calibration as files: for firmware, for analysis code, for a filter, and as pictures.

:mod:`.exporters` holds the table of formats and :func:`~.exporters.export_calibration`, and writes the JSON and the
C header; every other family of files is a module: :mod:`.tables` (YAML, CSV), :mod:`.params` (ArduPilot's and PX4's
accelerometer parameters), :mod:`.compass` (their compass parameters, and a compass calibrated from a flight),
:mod:`.noise` (Kalibr, OpenVINS, VINS-Fusion, the figures as JSON, the Allan table as CSV), :mod:`.temperature`
(the firmwares' temperature parameters, its JSON and its SVG), :mod:`.motioncal_packet` (the 68 bytes a board running
MotionCal's receiver stores) and :mod:`.snippets` (paste-ready lines that apply a calibration). The pictures are
exports too: :mod:`.allan_plot` (the Allan deviation) and :mod:`.flight_compass_plot` (a flight seen by its compass).
What they share — the file an export returns and each sensor's correction ``f = M (m − o)`` read from the typed
result — is :mod:`.common`.
"""
