/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * footer.c -- the footer of a result file: written and verified
 * (footer.h).
 */
#include "results/footer.h"

#include "util/crc32.h"
#include "util/text.h"

#include <errno.h>
#include <fcntl.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Where the bytes so far left the line being read. */
enum { FIRST_LINE = 0, LINE_START, IN_ROW, IN_OTHER };

void footer_start(footer_sum *s) { *s = (footer_sum){.crc = 0, .state = FIRST_LINE}; }

void footer_add(footer_sum *s, const void *buf, size_t n)
{
    const char *p = buf, *end = p + n;
    s->crc = crc32_update(s->crc, buf, n);
    s->bytes += n;
    while (p < end) {
        if (s->state == LINE_START) {
            if (*p == '\n') { /* an empty line */
                p++;
                continue;
            }
            s->state = *p == '#' ? IN_OTHER : IN_ROW;
        }
        const char *nl = memchr(p, '\n', (size_t)(end - p));
        if (!nl) return; /* the line goes on in the next buffer */
        if (s->state == IN_ROW) s->rows++;
        s->state = LINE_START;
        p = nl + 1;
    }
}

int footer_line(const footer_sum *s, char buf[FOOTER_SIZE])
{
    return snprintf(buf, FOOTER_SIZE, "# end: rows %" PRIu64 ", bytes %" PRIu64 ", crc32 %08" PRIx32 "\n",
                    s->rows, s->bytes, s->crc);
}

/* The footer's numbers, or -1 when `line` is not a footer. */
static int parse(const char *line, footer_info *f)
{
    char crc[9];
    int used = 0;
    if (sscanf(line, "# end: rows %" SCNu64 ", bytes %" SCNu64 ", crc32 %8[0-9a-f]%n", &f->rows,
               &f->bytes, crc, &used) != 3 || strcmp(line + used, "\n") != 0 || strlen(crc) != 8)
        return -1;
    f->crc = (uint32_t)strtoul(crc, NULL, 16);
    /* Exactly the text footer_line writes: no other spelling passes. */
    footer_sum s = {.crc = f->crc, .bytes = f->bytes, .rows = f->rows};
    char again[FOOTER_SIZE];
    footer_line(&s, again);
    return strcmp(again, line) == 0 ? 0 : -1;
}

int footer_verify(const char *path, footer_info *info, char **msg)
{
    *msg = NULL;
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    struct stat st;
    if (fd < 0) {
        *msg = text_printf("cannot read %s: %s", path, strerror(errno));
        return -1;
    }
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        *msg = text_printf("%s is not a regular file", path);
        close(fd);
        return -1;
    }
    /* The last line: the footer, at most FOOTER_SIZE - 1 bytes. */
    char tail[FOOTER_SIZE];
    const off_t size = st.st_size;
    const size_t want = size < (off_t)sizeof tail - 1 ? (size_t)size : sizeof tail - 1;
    ssize_t got = pread(fd, tail, want, size - (off_t)want);
    footer_info f;
    const char *line = NULL;
    if (got == (ssize_t)want) {
        tail[want] = '\0';
        /* the newline before the last line's */
        for (size_t i = want >= 2 ? want - 1 : 0; i-- > 0;)
            if (tail[i] == '\n') {
                line = tail + i + 1;
                break;
            }
        if (!line && (off_t)want == size) line = tail; /* the file is one line */
    }
    if (!line || parse(line, &f) != 0) {
        *msg = text_printf("%s has no footer line (# end: rows N, bytes N, crc32 X): cut short, "
                           "or not written whole by this version of taper", path);
        close(fd);
        return -1;
    }
    const uint64_t body = (uint64_t)size - strlen(line);
    if (f.bytes != body) {
        *msg = text_printf("%s: its footer counts %" PRIu64 " bytes above it, the file has %" PRIu64
                           ": cut or extended after it was written", path, f.bytes, body);
        close(fd);
        return -1;
    }
    footer_sum s;
    footer_start(&s);
    char *buf = malloc(1 << 16);
    uint64_t at = 0;
    int failed = !buf;
    while (!failed && at < body) {
        size_t n = body - at < (1u << 16) ? (size_t)(body - at) : 1u << 16;
        ssize_t r = pread(fd, buf, n, (off_t)at);
        if (r <= 0) {
            failed = 1;
            break;
        }
        footer_add(&s, buf, (size_t)r);
        at += (uint64_t)r;
    }
    free(buf);
    close(fd);
    if (failed) {
        *msg = text_printf("cannot read %s: %s", path, strerror(errno ? errno : EIO));
        return -1;
    }
    if (s.crc != f.crc) {
        *msg = text_printf("%s: its content does not match its footer (crc32 %08" PRIx32 ", the "
                           "footer says %08" PRIx32 "): changed after it was written", path, s.crc,
                           f.crc);
        return -1;
    }
    if (s.rows != f.rows) {
        *msg = text_printf("%s: %" PRIu64 " data rows, its footer says %" PRIu64, path, s.rows, f.rows);
        return -1;
    }
    if (info) *info = f;
    return 0;
}
