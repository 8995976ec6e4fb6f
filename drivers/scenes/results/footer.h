/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * footer.h -- the last line of every TSV result file, which proves the file
 * whole and unchanged:
 *
 *   # end: rows 200, bytes 34567, crc32 1a2b3c4d
 *
 * rows: the data rows above it (the lines that are neither the first line,
 * the column names, nor a '#' comment, nor empty); bytes: every byte above
 * it, the first line's included; crc32: the CRC-32 of those bytes (zlib's,
 * util/crc32.h), eight lowercase hex digits.  A '#' line: numpy, pandas
 * and gnuplot read the file as before.  Checked in Python by
 *
 *   data = open(path, 'rb').read()
 *   body, line = data[:data.rindex(b'\n', 0, -1) + 1], data[data.rindex(b'\n', 0, -1) + 1:]
 *   rows, size, crc = re.fullmatch(rb'# end: rows (\d+), bytes (\d+), crc32 ([0-9a-f]{8})\n', line).groups()
 *   assert int(size) == len(body) and int(crc, 16) == zlib.crc32(body)
 *
 * (docs/scene.md, "Result files").  The writer (results/output.c) adds it
 * when it commits a file; resume, the sweep's collectors and the Python
 * package's read_granules check it, and refuse a file that fails.
 *
 * Not part of libtaper.
 */
#ifndef TAPER_FOOTER_H
#define TAPER_FOOTER_H

#include <stddef.h>
#include <stdint.h>

/* Longest footer line, its newline and NUL included. */
#define FOOTER_SIZE 96

/* The running sums of a file's bytes. */
typedef struct footer_sum {
    uint32_t crc;
    uint64_t bytes, rows;
    int state; /* where the last byte left the line being read */
} footer_sum;

void footer_start(footer_sum *s);
void footer_add(footer_sum *s, const void *buf, size_t n);
/* The footer line of what was added, with its newline; its length. */
int footer_line(const footer_sum *s, char buf[FOOTER_SIZE]);

/* What a verified file's footer says. */
typedef struct footer_info {
    uint64_t rows, bytes;
    uint32_t crc;
} footer_info;

/* Reads `path` and checks its last line against the bytes above it.  0
 * (info filled, when not NULL), or -1 with *msg (malloc'd; NULL out of
 * memory) naming the path and what is wrong: not a regular file, no footer
 * (cut short, or not written whole by taper), a byte count, checksum or
 * row count that disagrees (changed or cut after it was written). */
int footer_verify(const char *path, footer_info *info, char **msg);

#endif
