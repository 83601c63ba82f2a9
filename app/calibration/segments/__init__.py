"""Where a recording rests: the still stretches a method is fitted on, found from the samples alone.

:mod:`.static` finds the rests of an upload's accelerometer (each labelled with the axis up, the other sensors still
too), which the still readings' methods and the recording's overview take; :mod:`.stationary_002` the fixed segments
of a long recording that auto-calibration takes (Farago et al., section II.B.1). The still part of a noise recording
is the noise's (:mod:`app.calibration.noise.still_part`, on :mod:`.static`'s rule), the cube's segmentation the
cube's (:mod:`app.calibration.cube.segmentation`).
"""
