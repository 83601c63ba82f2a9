"""Seeded simulations of the papers' experiments, for the tests, the benchmarks and the sample data.

A top-level package beside ``app``, left out of the wheel: it imports the core (it simulates its models), and no
module of ``app`` imports it (docs/architecture.md's import table, checked by ``tests/test_architecture.py``):

- :mod:`.triangular`: the simulation of Farago, Maczak and Gingl, IEEE Access, eqs. (17)–(20), and
  the Cramér–Rao bound of its 9-parameter model;
- :mod:`.autocal`: long recordings of rest and movement bouts through the same errors;
- :mod:`.logs`: raw accelerometer logs of a device rested in several orientations
  (the affine error of Georgieva et al., ESGI'95, section 3.2);
- :mod:`.cube`: the cube sessions of Särkkä et al., IEEE Sensors Journal 17(11) 2017, section V.
- :mod:`.gyro_captures`: still gyroscope captures with a known bias, white noise and a wander of the
  bias between captures.
"""
