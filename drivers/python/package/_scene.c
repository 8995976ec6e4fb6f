/*
 * _scene.c -- taper.run_scene's access to the driver's scene reader
 * (drivers/taper/scene/scene.h): the same parser, validation and defaults
 * as `taper SCENE.nml`, so a scene means the same thing from Python as from
 * the command line.  Nothing here reads the file itself.
 */
#include "_scene.h"

#include "scene/scene.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct pyscene {
    scene *sc;
};

int pyscene_load(const char *path, pyscene **out, char **diag)
{
    *out = NULL;
    *diag = NULL;
    pyscene *ps = calloc(1, sizeof *ps);
    if (!ps) return -2;
    if (!(ps->sc = scene_new(path))) {
        free(ps);
        return -2;
    }
    if (scene_load(ps->sc) == 0 && scene_validate(ps->sc) == 0) {
        *out = ps;
        return 0;
    }
    int rc = scene_error_count(ps->sc) ? -1 : -2;
    if (rc == -1) {
        /* The diagnostics exactly as the driver prints them on stderr. */
        size_t len = 0;
        FILE *mem = open_memstream(diag, &len);
        if (mem) {
            scene_print_diags(ps->sc, mem);
            fclose(mem);
            /* One message: drop the final newline. */
            if (*diag && len && (*diag)[len - 1] == '\n') (*diag)[len - 1] = '\0';
        }
    }
    pyscene_free(ps);
    return rc;
}

void pyscene_free(pyscene *ps)
{
    if (!ps) return;
    scene_free(ps->sc);
    free(ps);
}

size_t pyscene_runs(const pyscene *ps)
{
    return scene_cfg(ps->sc)->runs.n;
}

int pyscene_numerics(const pyscene *ps)
{
    return scene_cfg(ps->sc)->solver.numerics;
}

taper_status pyscene_specs(const pyscene *ps, size_t i, taper_chain_spec *chain,
                           taper_solver_spec *solver, taper_error *err)
{
    scene_config at; /* run i: every swept variable, solver ones too, at its value */
    scene_config_at(scene_cfg(ps->sc), i, &at);
    taper_status rc = scene_apply_chain(&at, 0, chain, err);
    if (rc == TAPER_OK) rc = scene_apply_solver(&at, solver, err);
    return rc;
}
