/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * output.h -- result files of the driver: tidy TSV (comment lines, one
 * header line, one row per granule) written atomically, so that a file
 * with a result's name is always a complete result.
 *
 * Not part of libtaper: the library never writes files.
 */
#ifndef TAPER_OUTPUT_H
#define TAPER_OUTPUT_H

#include <stddef.h>
#include <stdio.h>

/* Failures return -1 (or NULL) and set *msg to a message naming the path,
 * malloc'd (NULL only when out of memory): the caller prints and frees it. */

/* mkdir -p.  0 on success. */
int out_mkdir_p(const char *dir, char **msg);

/* A file being written under a temporary name in its final directory
 * (rename() is atomic only within one file system). */
typedef struct out_file {
    FILE *fp;
    char *tmp_path;
    char *final_path;
    int failed;        /* a write failed: commit refuses */
} out_file;

/* Opens DIR/.NAME.XXXXXX for writing.  NULL with *msg on failure. */
out_file *out_open(const char *dir, const char *name, char **msg);
/* Flushes, closes and renames to DIR/NAME.  Frees f.  0 or -1 with *msg
 * (the temporary file is removed on failure). */
int out_commit(out_file *f, char **msg);
/* Closes and removes the temporary file.  Frees f.  NULL is a no-op. */
void out_discard(out_file *f);

/* From a signal handler (async-signal-safe): removes the temporary file
 * being written, if any, so that a process killed while writing leaves
 * nothing hidden behind.  The rename of out_commit runs with SIGINT,
 * SIGTERM, SIGHUP and SIGXCPU blocked: a file is either still temporary
 * (removed here) or complete under its name. */
void out_signal_cleanup(void);

/* Removes DIR/NAME if present (a stale result from an earlier run).
 * 0 when absent afterwards, -1 with *msg otherwise. */
int out_remove(const char *dir, const char *name, char **msg);

/* TSV cells: %.17g, or "nan" for values that do not exist (any NaN), so
 * that every reader sees one spelling. */
void out_cell(FILE *fp, double x, int last);

/* The per-granule table: columns of length n (NULL columns print nan). */
#define OUT_N_COLUMNS 12
extern const char *const out_column_names[OUT_N_COLUMNS];
typedef struct out_columns {
    size_t n;
    const double *col[OUT_N_COLUMNS]; /* in the order of out_column_names;
                                         col[0] (k) is ignored: k = 1..n */
    unsigned set;                     /* bit c: column c written (k always);
                                         0: every column                  */
    size_t every;                     /* rows k = 1, 1 + every, ..., and n;
                                         0 or 1: every row                */
    const char *unit[OUT_N_COLUMNS];  /* NULL: none; else the header says
                                         NAME[UNIT] (SI results)          */
} out_columns;

/* The header line: the column names (after lead_name, unless NULL). */
void out_write_header(FILE *fp, const out_columns *cols, const char *lead_name);
/* The rows, each with a leading cell `lead` when lead_name is not NULL (the
 * swept value of a combined sweep table). */
void out_write_rows(FILE *fp, const out_columns *cols, const char *lead_name, double lead);

#endif
