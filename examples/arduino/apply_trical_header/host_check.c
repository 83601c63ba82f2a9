/* The example's correction built for the host (trical's tests compile it with gcc): reads readings,
 * three numbers a line, from standard input and prints each calibrated, three numbers a line. */
#include <stdio.h>

#include "trical_calibration.h"
#include "calibrate.h"

int main(void)
{
    float m[3], a[3];
    while (scanf("%f %f %f", &m[0], &m[1], &m[2]) == 3) {
        calibrate_accelerometer(m, a);
        printf("%.9g %.9g %.9g\n", (double)a[0], (double)a[1], (double)a[2]);
    }
    return 0;
}
