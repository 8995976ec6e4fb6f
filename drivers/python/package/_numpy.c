/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * _numpy.c -- numpy's C-API table for the extension, and its import on the
 * first call that needs it (core_numpy), not when the module is imported:
 * `import taper` costs no numpy import (docs/python.md, "Overheads").
 * _module.c and _scene.c call core_numpy before they touch a numpy object
 * or type.
 */
#define TAPER_CORE_IMPORTS_NUMPY
#include "_core.h"

#include <signal.h>

/* SIGINT while numpy is imported, noted (a signal handler's flag). */
static volatile sig_atomic_t sigint_noted;
static void note_sigint(int sig)
{
    (void)sig;
    sigint_noted = 1;
}

/* numpy's import, whole.  Ctrl-C during it (the first call that needs
 * numpy: 0.1 s and more) raised KeyboardInterrupt inside numpy's
 * initialisation, or an ImportError numpy made of it, and left numpy half
 * loaded: its extension cannot be loaded twice in a process, so every later
 * call failed ("cannot load module more than once per process") until the
 * interpreter was restarted.  So during the import SIGINT is only noted
 * (where Python's handler would act on it), and handed to Python once
 * numpy is whole: KeyboardInterrupt then, as always. */
static int import_numpy(void)
{
    static int importing; /* another thread's import is under way: the
                             import lock serialises them, its handler notes */
    PyOS_sighandler_t python_handler = PyOS_getsig(SIGINT);
    const int watch = !importing && python_handler != SIG_IGN && python_handler != SIG_DFL;
    if (watch) {
        importing = 1;
        sigint_noted = 0;
        PyOS_setsig(SIGINT, note_sigint);
    }
    int rc = _import_array();
    if (watch) {
        PyOS_setsig(SIGINT, python_handler);
        importing = 0;
        if (sigint_noted) PyErr_SetInterruptEx(SIGINT); /* as if it came now */
    }
    return rc;
}

int core_numpy(void)
{
    static int ready; /* written with the GIL held */
    if (ready) return 0;
    if (import_numpy() < 0) {
        if (!PyErr_Occurred()) PyErr_SetString(PyExc_ImportError, "numpy's C API did not load");
        return -1;
    }
    ready = 1;
    return PyErr_CheckSignals(); /* a Ctrl-C noted during the import */
}
