/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_measurements.c -- the tables a calibration reads
 * (drivers/scenes/optimise/measurements.h): taper's own files in all three
 * forms read back, any subset of rows and columns, units from the header;
 * and every bad table refused with an error naming FILE:LINE:COLUMN and
 * what to do: wrong units, unknown columns, nan, times before the run or
 * beyond it, granules beyond the chain, walls the chain lacks, rows of the
 * wrong length (suite 'optimise').
 */
#include "optimise/measurements.h"
#include "test_util.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char dir[] = "/tmp/taper-measurements-XXXXXX";

static int setup(void **state)
{
    (void)state;
    return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    return system(cmd) == 0 ? 0 : -1;
}

/* A file named `name` in the test's directory holding text; its path. */
static const char *file(const char *name, const char *text)
{
    static char path[256];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *fp = fopen(path, "w");
    assert_non_null(fp);
    fputs(text, fp);
    fclose(fp);
    return path;
}

static measurements *read_ok(const char *text, const char *columns)
{
    char *msg = NULL;
    measurements *m = meas_read(file("ok.tsv", text), columns, &msg);
    if (!m) fail_msg("refused: %s", msg);
    return m;
}

/* The table is refused with a message that starts FILE:where and holds
 * every one of the words (NULL-terminated). */
static void refused(const char *text, const char *columns, const char *where, ...)
{
    char *msg = NULL;
    const char *path = file("bad.tsv", text);
    measurements *m = meas_read(path, columns, &msg);
    if (m) fail_msg("accepted:\n%s", text);
    assert_non_null(msg);
    char head[300];
    snprintf(head, sizeof head, "%s:%s", path, where);
    if (where[0] && strncmp(msg, head, strlen(head)) != 0)
        fail_msg("'%s' does not start with '%s'", msg, head);
    va_list ap;
    va_start(ap, where);
    for (const char *w; (w = va_arg(ap, const char *));)
        if (!strstr(msg, w)) fail_msg("'%s' lacks '%s'", msg, w);
    va_end(ap);
    free(msg);
}

static void sensors_as_taper_writes_them(void **state)
{
    (void)state;
    measurements *m = read_ok(
        "t[s]\tgranule\tx[m]\tv[m/s]\tf_left[N]\tf_right[N]\tforce[N]\n"
        "# taper 1.0.0 sensors: granules 2 5\n"
        "0\t2\t0\t0\t0\t0\t0\n"
        "1e-06\t2\t1e-9\t0.01\t1.5\t0.5\t1\n"
        "1e-06\t5\t0\t0\t0\t0\t0\n",
        NULL);
    assert_int_equal(m->form, MEAS_SENSORS);
    assert_true(m->si);
    assert_int_equal(m->n_quantities, 5);
    assert_int_equal(m->n, 15);
    /* in the file's order: row by row, column by column */
    assert_int_equal(m->points[8].q, MEAS_F_RIGHT);
    assert_true(m->points[8].value == 0.5);
    assert_true(m->points[8].t == 1e-6);
    assert_int_equal(m->points[8].granule, 2);
    assert_int_equal(m->points[8].line, 4);
    assert_int_equal(m->points[8].column, 23); /* "1e-06\t2\t1e-9\t0.01\t1.5\t" */
    assert_true(m->peak[MEAS_F_LEFT] == 1.5);
    assert_true(meas_last_time(m) == 1e-6);
    meas_free(m);
    /* a subset of the columns, in any order, blanks or commas between */
    m = read_ok("# a comment before the header\n"
                "force[N], t[s] , granule\n"
                "2.5, 0.5e-5, 3   # a comment after a row\n"
                "\n"
                "3.5 1e-5 3\n",
                NULL);
    assert_int_equal(m->n, 2);
    assert_true(m->points[1].value == 3.5 && m->points[1].t == 1e-5);
    meas_free(m);
    /* the columns a scene chooses */
    m = read_ok("t\tgranule\tv\tforce\n0\t1\t1\t0\n", "force");
    assert_false(m->si);
    assert_int_equal(m->n_quantities, 1);
    assert_int_equal(m->quantity[0], MEAS_FORCE);
    assert_int_equal(m->n, 1);
    meas_free(m);
}

static void walls_and_granules(void **state)
{
    (void)state;
    measurements *m = read_ok("t[s]\tforce_right[N]\n# taper walls\n0\t0\n1e-5\t12.5\n", NULL);
    assert_int_equal(m->form, MEAS_WALLS);
    assert_int_equal(m->n, 2);
    assert_int_equal(m->points[1].q, MEAS_WALL_RIGHT);
    assert_int_equal(m->points[1].granule, 0);
    meas_free(m);
    /* granules.tsv: the chain's and the theory's columns are skipped */
    m = read_ok("k\tR[m]\tm[kg]\tX0[m]\tt_pass[s]\tT_res[s]\tv_peak[m/s]\ttheory_v[m/s]\n"
                "1\t0.002\t1e-4\t0\t1e-5\t1e-5\t0.5\tnan\n"
                "2\t0.002\t1e-4\t0.004\t2e-5\t1e-5\t0.4\tnan\n",
                "t_pass v_peak");
    assert_int_equal(m->form, MEAS_GRANULES);
    assert_int_equal(m->n, 4);
    assert_int_equal(m->points[3].granule, 2);
    assert_int_equal(m->points[3].q, MEAS_V_PEAK);
    assert_true(isnan(m->points[3].t));
    meas_free(m);
}

static void bad_headers(void **state)
{
    (void)state;
    /* wrong units: taper's unit named */
    refused("t[ms]\tgranule\tforce[N]\n0\t1\t0\n", NULL, "1:1:", "t[ms]", "in s", NULL);
    refused("t[s]\tgranule\tforce[kN]\n0\t1\t0\n", NULL, "1:", "force[kN]", "in N", NULL);
    refused("t[s]\tgranule[-]\tforce[N]\n0\t1\t0\n", NULL, "1:", "granule is a number", NULL);
    /* some columns with units, some without */
    refused("t[s]\tgranule\tforce\n0\t1\t0\n", NULL, "1:", "force", "has no", NULL);
    /* unknown columns, and another file's */
    refused("t[s]\tgranule\tforse[N]\n0\t1\t0\n", NULL, "1:", "unknown column 'forse'",
            "sensors.tsv", NULL);
    refused("t[s]\tgranule\tforce_right[N]\n0\t1\t0\n", NULL, "1:", "unknown column 'force_right'",
            NULL);
    refused("t[s]\tt[s]\tforce_right[N]\n0\t1\t0\n", NULL, "1:", "given twice", NULL);
    refused("time\tforce\n0\t1\n", NULL, "1:", "no column t, granule or k", NULL);
    refused("granule\tforce\n1\t1\n", NULL, "1:", "no column t", NULL);
    refused("t[s\tgranule\tforce\n0\t1\t0\n", NULL, "1:", "NAME[UNIT]", NULL);
    /* the scene asks for a column the data lack */
    refused("t\tgranule\tforce\n0\t1\t0\n", "v", "", "columns: 'v'", "it has: force", NULL);
    refused("", NULL, "", "empty", NULL);
    refused("t\tgranule\tforce\n# nothing measured\n", NULL, "", "no measurement", NULL);
    refused("k\tR\tm\n1\t1\t1\n", NULL, "", "no measured column", NULL);
}

static void bad_rows(void **state)
{
    (void)state;
    const char *head = "t[s]\tgranule\tforce[N]\n";
    char text[256];
    /* nan, at its line and column */
    snprintf(text, sizeof text, "%s0\t1\t0\n1e-6\t1\tnan\n", head);
    refused(text, NULL, "3:8:", "force[N]", "'nan' is not a measurement", NULL);
    snprintf(text, sizeof text, "%s0\t1\tinf\n", head);
    refused(text, NULL, "2:5:", "not a measurement", NULL);
    snprintf(text, sizeof text, "%s0\t1\t1.5x\n", head);
    refused(text, NULL, "2:5:", "'1.5x' is not a number", NULL);
    /* rows of the wrong length */
    snprintf(text, sizeof text, "%s0\t1\n", head);
    refused(text, NULL, "2:", "2 values", "3 columns", NULL);
    snprintf(text, sizeof text, "%s0\t1\t2\t3\n", head);
    refused(text, NULL, "2:7:", "4 values", NULL);
    /* granules and times */
    snprintf(text, sizeof text, "%s0\t1.5\t2\n", head);
    refused(text, NULL, "2:3:", "'1.5' is not a granule", NULL);
    snprintf(text, sizeof text, "%s0\t0\t2\n", head);
    refused(text, NULL, "2:3:", "not a granule", NULL);
    snprintf(text, sizeof text, "%s-1e-6\t1\t2\n", head);
    refused(text, NULL, "2:1:", "before the run's start", NULL);
    /* a nan in a column not fitted is no measurement, and no error */
    measurements *m = read_ok("t\tgranule\tv\tforce\n0\t1\tnan\t2\n", "force");
    assert_int_equal(m->n, 1);
    meas_free(m);
}

static void checked_against_the_run(void **state)
{
    (void)state;
    char *msg = NULL;
    measurements *m = meas_read(file("run.tsv", "t[s]\tgranule\tforce[N]\n"
                                                "0\t1\t0\n"
                                                "1e-4\t7\t1\n"
                                                "3e-4\t2\t1\n"),
                                NULL, &msg);
    assert_non_null(m);
    meas_run_limits lim = {.n_granules = 10};
    assert_int_equal(meas_check(m, &lim, &msg), 0);
    lim.n_granules = 6; /* granule 7 of line 3 is beyond */
    assert_int_equal(meas_check(m, &lim, &msg), -1);
    assert_non_null(strstr(msg, "run.tsv:3:2: granule 7 is beyond the chain (n_granules = 6)"));
    free(msg);
    lim.n_granules = 10;
    lim.t_end = 2e-4; /* line 4 is after t_end */
    assert_int_equal(meas_check(m, &lim, &msg), -1);
    assert_non_null(strstr(msg, "run.tsv:4:1: time 0.0003 s is beyond the run"));
    assert_non_null(strstr(msg, "t_end"));
    free(msg);
    lim.t_end = 0;
    lim.t_max = 3e-4; /* a run stopped by t_max at the time itself has no sample there */
    assert_int_equal(meas_check(m, &lim, &msg), -1);
    assert_non_null(strstr(msg, "t_max"));
    free(msg);
    meas_free(m);
    m = meas_read(file("walls.tsv", "t[s]\tforce_left[N]\n0\t0\n"), NULL, &msg);
    assert_non_null(m);
    lim = (meas_run_limits){.n_granules = 10, .wall_right = 1};
    assert_int_equal(meas_check(m, &lim, &msg), -1);
    assert_non_null(strstr(msg, "walls.tsv:2:3: force_left: the scene has no left wall"));
    free(msg);
    meas_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sensors_as_taper_writes_them),
        cmocka_unit_test(walls_and_granules),
        cmocka_unit_test(bad_headers),
        cmocka_unit_test(bad_rows),
        cmocka_unit_test(checked_against_the_run),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
