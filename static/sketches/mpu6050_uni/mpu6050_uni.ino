// MPU-6050 (Adafruit_MPU6050, Adafruit Unified Sensor): one Uni: line per reading at about 100 Hz,
// accelerometer m/s^2, gyroscope rad/s, magnetometer uT (the MPU-6050 has none: zeros, which trical
// leaves out). trical reads these lines live (trical capture PORT, or the page's Connect a board).
#include <Adafruit_MPU6050.h>
#include <Adafruit_Sensor.h>
#include <Wire.h>

Adafruit_MPU6050 mpu;
const unsigned long PERIOD_US = 10000;  // 100 Hz
unsigned long next_us;

void setup() {
  Serial.begin(115200);
  while (!Serial) delay(10);
  if (!mpu.begin()) {
    Serial.println("MPU-6050 not found: check the wiring (SDA, SCL, 3V3, GND)");
    while (1) delay(100);
  }
  mpu.setAccelerometerRange(MPU6050_RANGE_2_G);
  mpu.setGyroRange(MPU6050_RANGE_250_DEG);
  mpu.setFilterBandwidth(MPU6050_BAND_44_HZ);
  next_us = micros();
}

void loop() {
  if ((long)(micros() - next_us) < 0) return;
  next_us += PERIOD_US;
  sensors_event_t a, g, temp;
  mpu.getEvent(&a, &g, &temp);
  Serial.print("Uni:");
  Serial.print(a.acceleration.x, 4); Serial.print(',');
  Serial.print(a.acceleration.y, 4); Serial.print(',');
  Serial.print(a.acceleration.z, 4); Serial.print(',');
  Serial.print(g.gyro.x, 5); Serial.print(',');
  Serial.print(g.gyro.y, 5); Serial.print(',');
  Serial.print(g.gyro.z, 5);
  Serial.println(",0,0,0");
}
