"""Noise: a still recording's noise characterised by its Allan deviation.

:mod:`.characterise` is the method (``characterise_noise`` and its result, ``NoiseResult``); :mod:`.still_part` the
stretch still on every sensor the recording holds, which it is read from (and a temperature calibration's rests);
:mod:`.allan` the overlapping Allan deviation, its confidence intervals and the noise terms read from its slopes, its
sums in the one compiled loop of the core (``allan_fused.pyx``, Cython; the same sums in numpy where it was not
built); :mod:`.spikes` the single samples far off their neighbours, replaced before the deviation is taken.
"""
