/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * text.h -- allocated strings for the driver: messages and paths are as
 * long as they need to be, never cut at a buffer's size.
 */
#ifndef TAPER_TEXT_H
#define TAPER_TEXT_H

#include <stdarg.h>

#if defined(__GNUC__) || defined(__clang__)
#define TEXT_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define TEXT_PRINTF(a, b)
#endif

/* printf into a malloc'd string; NULL only when out of memory. */
char *text_printf(const char *fmt, ...) TEXT_PRINTF(1, 2);
char *text_vprintf(const char *fmt, va_list ap);
/* A malloc'd copy; NULL only when out of memory. */
char *text_dup(const char *s);

#endif
