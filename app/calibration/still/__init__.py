"""The still readings: poses held still, and the models fitted on their means.

The six-position closed form and the affine fit on known orientations (:mod:`.affine`), the non-orthogonal model
(:mod:`.nonorthogonal`) and the triangular model on unknown orientations (:mod:`.triangular`, its solvers named in
:mod:`.solvers`, its microcontroller's fixed-point gradient descent in :mod:`.fixed_point`); what they are judged by
(:mod:`.cross_validation`, :mod:`.trust`, :mod:`.comparison`: the scale-and-offset fits the papers compare against);
which pose to add next (:mod:`.advice`); the gyroscope's bias from the same still captures (:mod:`.gyro_bias`); the
firmwares' offset-and-scale model fitted on them (:mod:`.firmware_model`); and the error of ignoring non-orthogonal
axes (:mod:`.nonorthogonality_error`).
"""
