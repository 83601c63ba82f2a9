"""Seeded simulations of the papers' experiments, for the tests, the benchmarks and the sample data.

Nothing the service runs imports this package (``tests/calibration/test_import_path.py`` checks it):

- :mod:`.triangular`: the simulation of Farago, Maczak and Gingl, IEEE Access, eqs. (17)–(20), and
  the Cramér–Rao bound of its 9-parameter model;
- :mod:`.autocal`: long recordings of rest and movement bouts through the same errors;
- :mod:`.logs`: raw accelerometer logs of a device rested in several orientations
  (the affine error of Georgieva et al., ESGI'95, section 3.2);
- :mod:`.cube`: the cube sessions of Särkkä et al., IEEE Sensors Journal 17(11) 2017, section V.
- :mod:`.gyro_captures`: still gyroscope captures with a known bias, white noise and a wander of the
  bias between captures.
"""
