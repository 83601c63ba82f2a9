// Apply a trical calibration on the board: the whole model a = M (m - o), scales and cross terms
// included (MotionCal's packet carries the offsets only). Export the header next to this sketch:
//   trical export cal_... --format c -o trical_calibration.h
// then build. The calibrated readings are printed as Uni: lines, so that trical can check them.
// The correction itself is plain C (calibrate.h), compiled and checked on the host by trical's tests.
#include <Adafruit_MPU6050.h>
#include <Adafruit_Sensor.h>
#include <Wire.h>

#include "trical_calibration.h"
#include "calibrate.h"

Adafruit_MPU6050 mpu;

void setup() {
  Serial.begin(115200);
  while (!Serial) delay(10);
  if (!mpu.begin()) {
    Serial.println("MPU-6050 not found: check the wiring");
    while (1) delay(100);
  }
  mpu.setAccelerometerRange(MPU6050_RANGE_2_G);  // the range the calibration was made at
}

void loop() {
  sensors_event_t a, g, temp;
  mpu.getEvent(&a, &g, &temp);
  float raw[3] = {a.acceleration.x, a.acceleration.y, a.acceleration.z};
  float out[3];
  calibrate_accelerometer(raw, out);
  Serial.print("Uni:");
  Serial.print(out[0], 4); Serial.print(',');
  Serial.print(out[1], 4); Serial.print(',');
  Serial.print(out[2], 4);
  Serial.println(",0,0,0,0,0,0");
  delay(10);
}
