/*
 * fortran_abi.c -- the C side of test_fortran_abi.f90: sizes and field
 * offsets of the two structs of taper.h that the Fortran module declares
 * as bind(C) derived types, taper_error and taper_progress (the library
 * fills them and only ever appends fields).  Every other object is opaque
 * and reached through functions, so it has no layout to agree on.
 */
#include "taper.h"

#include <stddef.h>

#define N_FIELDS 8

/* layout[type][0] = sizeof, layout[type][1 + i] = offset of field i. */
static const size_t layout[][N_FIELDS] = {
    {sizeof(taper_error), offsetof(taper_error, status), offsetof(taper_error, field),
     offsetof(taper_error, message)},
    {sizeof(taper_progress), offsetof(taper_progress, granule), offsetof(taper_progress, target),
     offsetof(taper_progress, t), offsetof(taper_progress, steps),
     offsetof(taper_progress, window_lo), offsetof(taper_progress, window_hi)},
};

/* field 0: sizeof; field i >= 1: offset of the i-th member. */
size_t taper_test_layout(int type, int field);
size_t taper_test_layout(int type, int field)
{
    if (type < 0 || type >= (int)(sizeof layout / sizeof layout[0]) || field < 0 || field >= N_FIELDS)
        return (size_t)-1;
    return layout[type][field];
}
