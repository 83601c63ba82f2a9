/* A receiver of MotionCal's 68-byte calibration packet, written for trical's tests independently of
 * app/io/exports/motioncal_packet.py: it reads the bytes a board would receive from standard input, checks the
 * length, the signature 117, 84 and the CRC-16 (polynomial 0xA001 reflected, from 0xFFFF, run over all
 * 68 bytes to zero), and prints the sixteen floats, one a line, with 9 significant digits (enough to
 * round-trip a float32). It refuses a bad packet with status 1 and a reason on standard error.
 * Build: gcc -std=c99 -Wall -Wextra -Werror -o motioncal_receiver motioncal_receiver.c */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#define PACKET_SIZE 68
#define N_FLOATS 16

static uint16_t crc_step(uint16_t crc, uint8_t byte)
{
    crc = (uint16_t)(crc ^ byte);
    for (int bit = 0; bit < 8; ++bit) {
        if (crc & 1u)
            crc = (uint16_t)((crc >> 1) ^ 0xA001u);
        else
            crc = (uint16_t)(crc >> 1);
    }
    return crc;
}

static float float_le(const uint8_t *p)
{
    uint32_t bits = (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
}

int main(void)
{
    uint8_t buf[PACKET_SIZE + 1];
    size_t n = fread(buf, 1, sizeof buf, stdin);
    if (n != PACKET_SIZE) {
        fprintf(stderr, "refused: %zu bytes, not %d\n", n, PACKET_SIZE);
        return 1;
    }
    if (buf[0] != 117 || buf[1] != 84) {
        fprintf(stderr, "refused: signature %u %u\n", buf[0], buf[1]);
        return 1;
    }
    uint16_t crc = 0xFFFF;
    for (int i = 0; i < PACKET_SIZE; ++i)
        crc = crc_step(crc, buf[i]);
    if (crc != 0) {
        fprintf(stderr, "refused: crc 0x%04x\n", crc);
        return 1;
    }
    /* accel zero-g 3, gyro zero-rate 3, mag hard iron 3, field 1, soft iron 00 11 22 01 02 12 */
    for (int k = 0; k < N_FLOATS; ++k)
        printf("%.9g\n", (double)float_le(buf + 2 + 4 * k));
    return 0;
}
