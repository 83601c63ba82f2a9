// LSM6DSOX + LIS3MDL (Adafruit's 9-DoF FeatherWing and breakouts; Adafruit_LSM6DS, Adafruit_LIS3MDL,
// Adafruit Unified Sensor): one Uni: line per reading at about 100 Hz, m/s^2, rad/s and uT.
// For an LSM6DS33 or LSM6DS3TR-C use that class of Adafruit_LSM6DS instead of Adafruit_LSM6DSOX.
#include <Adafruit_LIS3MDL.h>
#include <Adafruit_LSM6DSOX.h>
#include <Adafruit_Sensor.h>
#include <Wire.h>

Adafruit_LSM6DSOX imu;
Adafruit_LIS3MDL compass;
const unsigned long PERIOD_US = 10000;  // 100 Hz
unsigned long next_us;

static void print3(float x, float y, float z, int digits) {
  Serial.print(x, digits); Serial.print(',');
  Serial.print(y, digits); Serial.print(',');
  Serial.print(z, digits);
}

void setup() {
  Serial.begin(115200);
  while (!Serial) delay(10);
  if (!imu.begin_I2C() || !compass.begin_I2C()) {
    Serial.println("LSM6DSOX or LIS3MDL not found: check the wiring");
    while (1) delay(100);
  }
  imu.setAccelRange(LSM6DS_ACCEL_RANGE_2_G);
  imu.setGyroRange(LSM6DS_GYRO_RANGE_250_DPS);
  imu.setAccelDataRate(LSM6DS_RATE_104_HZ);
  imu.setGyroDataRate(LSM6DS_RATE_104_HZ);
  compass.setRange(LIS3MDL_RANGE_4_GAUSS);
  compass.setDataRate(LIS3MDL_DATARATE_155_HZ);
  compass.setPerformanceMode(LIS3MDL_HIGHMODE);
  next_us = micros();
}

void loop() {
  if ((long)(micros() - next_us) < 0) return;
  next_us += PERIOD_US;
  sensors_event_t accel, gyro, temp, mag;
  imu.getEvent(&accel, &gyro, &temp);
  compass.getEvent(&mag);
  Serial.print("Uni:");
  print3(accel.acceleration.x, accel.acceleration.y, accel.acceleration.z, 4); Serial.print(',');
  print3(gyro.gyro.x, gyro.gyro.y, gyro.gyro.z, 5); Serial.print(',');
  print3(mag.magnetic.x, mag.magnetic.y, mag.magnetic.z, 3);
  Serial.println();
}
