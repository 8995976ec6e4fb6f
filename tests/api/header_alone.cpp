/* SPDX-License-Identifier: GPL-3.0-or-later */
// header_alone.cpp -- taper.h as C++ (-Wall -Wextra -pedantic -Werror):
// the same program as header_alone.c, so both languages see every type.
#include "header_alone.c"
