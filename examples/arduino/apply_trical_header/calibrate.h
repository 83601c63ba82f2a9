/* The board side of a trical calibration, in plain C so that it builds for the host too: include the
 * header trical exports (trical export ID --format c -o trical_calibration.h) before this file. */
#ifndef TRICAL_EXAMPLE_CALIBRATE_H
#define TRICAL_EXAMPLE_CALIBRATE_H

/* a = M (m - o): the accelerometer reading m (in the unit it was calibrated in) corrected. */
static inline void calibrate_accelerometer(const float m[3], float a[3])
{
    trical_acc_apply(m, a);
}

#endif
