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
    int failed;        /* a write failed: commit refuses                     */
    int footer;        /* a .tsv: out_commit ends it with its footer
                          (results/footer.h)                                */
    int stoppable;     /* OUT_WHOLE: a stop signal stops it                   */
    int stopped;       /* so stopped: out_commit removes it                  */
    int slot;          /* its place among the temporaries a second signal
                          removes (out_signal_cleanup), -1: none            */
} out_file;

/* Opens DIR/.NAME.XXXXXX for writing.  NULL with *msg on failure (also
 * when a stop signal came before, in OUT_WHOLE mode: out_was_stopped). */
out_file *out_open(const char *dir, const char *name, char **msg);
/* Flushes, ends a .tsv with its footer (row count and CRC-32 of every byte
 * above it, results/footer.h), syncs, closes and renames to DIR/NAME.
 * Frees f.  0 or -1 with *msg: a write that failed (ENOSPC, EIO, EFBIG
 * beyond `ulimit -f`) or was stopped by a signal (out_stopping) removes the
 * temporary file, so that nothing with a result's name is half written. */
int out_commit(out_file *f, char **msg);
/* Closes and removes the temporary file.  Frees f.  NULL is a no-op. */
void out_discard(out_file *f);

/* The program's stop signal, 0 if none (run/interrupt.c sets it once):
 * writers look between rows (out_stopping). */
void out_set_stop_check(int (*stop_signal)(void));
/* The stop signal, 0 if none (gnuplot, which renders a figure, is stopped
 * at it too: results/plot.c). */
int out_stop_signal(void);

/* What the files the calling thread opens are:
 *   OUT_WHOLE  results of a complete run, sweep and report files (the
 *              default): a stop signal stops the file being written (its
 *              temporary removed) and every one opened after it (out_open
 *              fails), so that nothing is half written and nothing starts
 *              after the signal;
 *   OUT_FOUND  what a run a signal interrupted had found (granules.partial.tsv
 *              and its time series): written whole after the signal; a
 *              second signal ends the process (out_signal_cleanup). */
typedef enum out_mode { OUT_WHOLE = 0, OUT_FOUND = 1 } out_mode;
void out_set_mode(out_mode mode);
/* Non-zero once f is to stop (OUT_WHOLE and a stop signal).  Writers of
 * long files ask every few thousand rows and return; out_commit then
 * removes the file and fails with out_stopped_message. */
int out_stopping(out_file *f);
/* "DIR/NAME not written: interrupted by a signal" (malloc'd). */
char *out_stopped_message(const out_file *f);
/* 1 when msg (of a failed out_open or out_commit) says a stop signal ended
 * the write, not a failure of the disk. */
int out_was_stopped(const char *msg);

/* From a signal handler (async-signal-safe): removes the temporary files
 * being written, if any (one per writing thread), so that a process killed
 * while writing leaves nothing hidden behind.  The rename of out_commit
 * runs with SIGINT, SIGTERM, SIGHUP and SIGXCPU blocked: a file is either
 * still temporary (removed here) or complete under its name. */
void out_signal_cleanup(void);

/* Removes the temporary files of out_open for each of names[0..n) in dir
 * (DIR/.NAME.XXXXXX), left by a process killed while writing (SIGKILL,
 * power loss); the caller holds the directory's lock, so no other taper
 * writes them.  Returns how many were removed. */
size_t out_remove_temporaries(const char *dir, const char *const *names, size_t n);

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
 * swept value of a combined sweep table).  Stops early when out_stopping. */
void out_write_rows(out_file *f, const out_columns *cols, const char *lead_name, double lead);

#endif
