/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * crc32.h -- CRC-32 as zlib, gzip, PNG and Python's zlib.crc32 compute it
 * (ISO-HDLC: polynomial 0x04C11DB7 reflected, initial value and final xor
 * 0xFFFFFFFF; the CRC of "123456789" is cbf43926), so that a user checks a
 * result file's footer with a line of Python (results/footer.h).
 */
#ifndef TAPER_CRC32_H
#define TAPER_CRC32_H

#include <stddef.h>
#include <stdint.h>

/* The CRC of the bytes so far extended by buf[0..n); start with crc = 0
 * (zlib.crc32(data, crc) alike).  Thread-safe. */
uint32_t crc32_update(uint32_t crc, const void *buf, size_t n);

#endif
