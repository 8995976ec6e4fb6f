/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * scene_cite.c -- what to cite for a scene: BibTeX entries for taper, the
 * paper it implements, and the solvers and physical models the scene's runs
 * use, as REBOUND's sim.cite() does (`taper --cite`, `taper SCENE --cite`,
 * taper.cite()).
 *
 * An entry is printed only when some run of the scene uses what it
 * describes: SUNDIALS where CVODE integrates (methods adams and bdf), GSL
 * where the binary collision theory describes the chain (its collision time
 * uses Gamma functions, eq. (18)), where rk8 integrates or a fit runs, and
 * the papers of the contact models a scene switches on.  Whether the theory
 * describes a chain is the library's answer (taper_chain_theory_note), not
 * a copy of its rules.
 */
#include "scene.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* The year of the release in CITATION.cff (test `cite` checks that the two
 * agree, and taper_version() with its version). */
#define TAPER_RELEASE_YEAR "2026"

typedef enum cite_work {
    CITE_PAPER,        /* the binary collision approximation: always           */
    CITE_SUNDIALS,     /* CVODE: the two papers SUNDIALS asks users to cite    */
    CITE_GSL,          /* the theory's Gamma functions, rk8pd, the fits        */
    CITE_RK8PD,        /* the Prince-Dormand pair of method rk8                */
    CITE_DAMPING,      /* viscoelastic contacts                                */
    CITE_LOAD,         /* a static load: the Hertz chain under precompression  */
    CITE_DECORATED,    /* the effective chain of decorated profiles            */
    CITE_N_WORKS
} cite_work;

static const char *const entries[CITE_N_WORKS] = {
    [CITE_PAPER] =
        "@article{harbola2009tapered,\n"
        "  author = {Harbola, Upendra and Rosas, Alexandre and Esposito, Massimiliano and "
        "Lindenberg, Katja},\n"
        "  title = {Pulse propagation in tapered granular chains: An analytic study},\n"
        "  journal = {Physical Review E},\n"
        "  volume = {80},\n"
        "  number = {3},\n"
        "  pages = {031303},\n"
        "  year = {2009},\n"
        "  doi = {10.1103/PhysRevE.80.031303},\n"
        "  eprint = {0905.4512},\n"
        "  archivePrefix = {arXiv}\n"
        "}\n",
    [CITE_SUNDIALS] =
        "@article{gardner2022sundials,\n"
        "  author = {Gardner, David J. and Reynolds, Daniel R. and Woodward, Carol S. and "
        "Balos, Cody J.},\n"
        "  title = {Enabling new flexibility in the {SUNDIALS} suite of nonlinear and "
        "differential/algebraic equation solvers},\n"
        "  journal = {ACM Transactions on Mathematical Software},\n"
        "  volume = {48},\n"
        "  number = {3},\n"
        "  pages = {31:1--31:24},\n"
        "  year = {2022},\n"
        "  doi = {10.1145/3539801}\n"
        "}\n"
        "\n"
        "@article{hindmarsh2005sundials,\n"
        "  author = {Hindmarsh, Alan C. and Brown, Peter N. and Grant, Keith E. and Lee, Steven L. "
        "and Serban, Radu and Shumaker, Dan E. and Woodward, Carol S.},\n"
        "  title = {{SUNDIALS}: Suite of nonlinear and differential/algebraic equation solvers},\n"
        "  journal = {ACM Transactions on Mathematical Software},\n"
        "  volume = {31},\n"
        "  number = {3},\n"
        "  pages = {363--396},\n"
        "  year = {2005},\n"
        "  doi = {10.1145/1089014.1089020}\n"
        "}\n",
    [CITE_GSL] =
        "@book{galassi2009gsl,\n"
        "  author = {Galassi, Mark and Davies, Jim and Theiler, James and Gough, Brian and "
        "Jungman, Gerard and Alken, Patrick and Booth, Michael and Rossi, Fabrice},\n"
        "  title = {{GNU} Scientific Library Reference Manual},\n"
        "  edition = {Third},\n"
        "  publisher = {Network Theory Ltd.},\n"
        "  year = {2009},\n"
        "  isbn = {0954612078}\n"
        "}\n",
    [CITE_RK8PD] =
        "@article{prince1981high,\n"
        "  author = {Prince, P. J. and Dormand, J. R.},\n"
        "  title = {High order embedded {Runge-Kutta} formulae},\n"
        "  journal = {Journal of Computational and Applied Mathematics},\n"
        "  volume = {7},\n"
        "  number = {1},\n"
        "  pages = {67--75},\n"
        "  year = {1981},\n"
        "  doi = {10.1016/0771-050X(81)90010-3}\n"
        "}\n",
    [CITE_DAMPING] =
        "@article{kuwabara1987restitution,\n"
        "  author = {Kuwabara, Gen and Kono, Kimitoshi},\n"
        "  title = {Restitution coefficient in a collision between two spheres},\n"
        "  journal = {Japanese Journal of Applied Physics},\n"
        "  volume = {26},\n"
        "  number = {8},\n"
        "  pages = {1230--1233},\n"
        "  year = {1987},\n"
        "  doi = {10.1143/JJAP.26.1230}\n"
        "}\n"
        "\n"
        "@article{brilliantov1996model,\n"
        "  author = {Brilliantov, Nikolai V. and Spahn, Frank and Hertzsch, Jan-Martin and "
        "P{\\\"o}schel, Thorsten},\n"
        "  title = {Model for collisions in granular gases},\n"
        "  journal = {Physical Review E},\n"
        "  volume = {53},\n"
        "  number = {5},\n"
        "  pages = {5382--5392},\n"
        "  year = {1996},\n"
        "  doi = {10.1103/PhysRevE.53.5382}\n"
        "}\n",
    [CITE_LOAD] =
        "@book{nesterenko2001dynamics,\n"
        "  author = {Nesterenko, Vitali F.},\n"
        "  title = {Dynamics of Heterogeneous Materials},\n"
        "  publisher = {Springer},\n"
        "  address = {New York},\n"
        "  year = {2001},\n"
        "  doi = {10.1007/978-1-4757-3524-6}\n"
        "}\n",
    [CITE_DECORATED] =
        "@article{harbola2009decorated,\n"
        "  author = {Harbola, Upendra and Rosas, Alexandre and Romero, Aldo H. and "
        "Lindenberg, Katja},\n"
        "  title = {Pulse propagation in decorated granular chains: An analytical approach},\n"
        "  journal = {Physical Review E},\n"
        "  volume = {80},\n"
        "  number = {5},\n"
        "  pages = {051302},\n"
        "  year = {2009},\n"
        "  doi = {10.1103/PhysRevE.80.051302},\n"
        "  eprint = {0909.2627},\n"
        "  archivePrefix = {arXiv}\n"
        "}\n",
};

/* Does the binary collision theory describe the chain of run `point`?  The
 * library decides (taper_chain_theory_note); -1 when the chain cannot be
 * built (memory: a validated scene has no other failure). */
static int theory_describes(const scene_config *cfg, size_t point)
{
    taper_chain_spec *spec = scene_chain_spec(cfg, point, NULL);
    taper_chain *chain = spec ? taper_chain_alloc(spec, NULL) : NULL;
    int describes = chain ? taper_chain_theory_note(chain) == NULL : -1;
    taper_chain_free(chain);
    taper_chain_spec_free(spec);
    return describes;
}

#define WORK(w) (1u << (w))

/* Adds to *works what run `point` uses.  0, or -1 out of memory. */
static int mark_run(const scene_config *cfg, size_t point, unsigned *works)
{
    scene_config at;
    scene_config_at(cfg, point, &at);
    if (at.solver.numerics)
        *works |= scene_setting(&at, "method") == TAPER_RK8 ? WORK(CITE_GSL) | WORK(CITE_RK8PD)
                                                             : WORK(CITE_SUNDIALS);
    if (scene_setting(&at, "damping") > 0.0) *works |= WORK(CITE_DAMPING);
    if (scene_setting(&at, "load") > 0.0) *works |= WORK(CITE_LOAD);
    if (at.runs.fit) *works |= WORK(CITE_GSL);
    /* The decorated profile's theory is the effective chain.  The chain is
     * built only when the answer can still add an entry. */
    const int decorated = scene_setting(&at, "profile") == TAPER_DECORATED;
    if (!(*works & WORK(CITE_GSL)) || (decorated && !(*works & WORK(CITE_DECORATED)))) {
        const int describes = theory_describes(cfg, point);
        if (describes < 0) return -1;
        if (describes) *works |= WORK(CITE_GSL) | (decorated ? WORK(CITE_DECORATED) : 0u);
    }
    return 0;
}

int scene_cite_mark(const scene *sc, unsigned *works)
{
    const scene_config *cfg = scene_cfg(sc);
    *works |= WORK(CITE_PAPER);
    for (size_t point = 0; point < cfg->runs.n; point++)
        if (mark_run(cfg, point, works) != 0) return -1;
    return 0;
}

int scene_write_citations(unsigned works, FILE *fp)
{
    fprintf(fp,
            "%% What to cite (taper --cite): taper, the paper it implements, and the solvers\n"
            "%% and models the runs use.\n"
            "@misc{taper,\n"
            "  author = {{The taper developers}},\n"
            "  title = {taper: pulse propagation in tapered granular chains},\n"
            "  note = {Version %s, licensed GPL-3.0-or-later},\n"
            "  year = {" TAPER_RELEASE_YEAR "}\n"
            "}\n",
            taper_version());
    for (int w = 0; w < CITE_N_WORKS; w++)
        if (works & WORK(w)) fprintf(fp, "\n%s", entries[w]);
    return ferror(fp) ? -1 : 0;
}
