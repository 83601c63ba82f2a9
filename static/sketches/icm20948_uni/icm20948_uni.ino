// ICM-20948 (Adafruit_ICM20X, Adafruit Unified Sensor): one Uni: line per reading at about 100 Hz,
// m/s^2, rad/s and uT (its AK09916 magnetometer).
#include <Adafruit_ICM20948.h>
#include <Adafruit_Sensor.h>
#include <Wire.h>

Adafruit_ICM20948 icm;
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
  if (!icm.begin_I2C()) {
    Serial.println("ICM-20948 not found: check the wiring");
    while (1) delay(100);
  }
  icm.setAccelRange(ICM20948_ACCEL_RANGE_2_G);
  icm.setGyroRange(ICM20948_GYRO_RANGE_250_DPS);
  icm.setMagDataRate(AK09916_MAG_DATARATE_100_HZ);
  next_us = micros();
}

void loop() {
  if ((long)(micros() - next_us) < 0) return;
  next_us += PERIOD_US;
  sensors_event_t accel, gyro, temp, mag;
  icm.getEvent(&accel, &gyro, &temp, &mag);
  Serial.print("Uni:");
  print3(accel.acceleration.x, accel.acceleration.y, accel.acceleration.z, 4); Serial.print(',');
  print3(gyro.gyro.x, gyro.gyro.y, gyro.gyro.z, 5); Serial.print(',');
  print3(mag.magnetic.x, mag.magnetic.y, mag.magnetic.z, 3);
  Serial.println();
}
