/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * disorder.c -- the random factors of a disordered chain, reproducible on
 * every machine and for every N (docs/physics.md, "Disorder").
 *
 * u_k is drawn from (seed, k) alone by a counter-based generator: the k-th
 * output of SplitMix64 (Steele, Lea and Flood, "Fast splittable
 * pseudorandom number generators", OOPSLA 2014; the generator of Java's
 * SplittableRandom) started from state `seed`,
 *
 *     z = seed + k * 0x9E3779B97F4A7C15              (mod 2^64)
 *     z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9
 *     z = (z ^ (z >> 27)) * 0x94D049BB133111EB
 *     z =  z ^ (z >> 31)
 *     u_k = 2 (z >> 11) 2^-53 - 1                    in [-1, 1)
 *
 * Only unsigned 64-bit arithmetic and one exact conversion to double: the
 * same bits on every compiler and machine, and granule k's factor does not
 * depend on how many granules come before or after it.
 */
#include "chain/chain_impl.h"

double chain_disorder_uniform(uint64_t seed, uint64_t k)
{
    uint64_t z = seed + k * UINT64_C(0x9E3779B97F4A7C15);
    z = (z ^ (z >> 30)) * UINT64_C(0xBF58476D1CE4E5B9);
    z = (z ^ (z >> 27)) * UINT64_C(0x94D049BB133111EB);
    z = z ^ (z >> 31);
    /* 53 random bits: an exact double in [0, 1), then [-1, 1). */
    double u01 = (double)(z >> 11) * 0x1.0p-53;
    return 2.0 * u01 - 1.0;
}
