/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * stepper_rk8_tableau.h -- the coefficients of method rk8: Prince and
 * Dormand's 8(7) pair RK8(7)13M (P. J. Prince and J. R. Dormand, "High
 * order embedded Runge-Kutta formulae", J. Comput. Appl. Math. 7 (1981)
 * 67-75), with the rational approximations GSL uses
 * (ode-initval2/rk8pd.c, GSL 2.7), digit for digit.  Only numbers: the
 * arithmetic is stepper_rk8.c's.  A leaf.
 *
 * Stage i (1..13) is k_i = f(t + c_i h, y + h sum_j a_ij k_j); the step
 * is y1 = y + h sum_i b_i k_i (order 8), and its error estimate
 * h (sum_i bhat_i k_i - sum_i b_i k_i), bhat of order 7, as GSL computes it.
 */
#ifndef TAPER_STEPPER_RK8_TABLEAU_H
#define TAPER_STEPPER_RK8_TABLEAU_H

/* c_2..c_11 (c_12 = c_13 = 1) */
#define RK8_C2 (1.0 / 18.0)
#define RK8_C3 (1.0 / 12.0)
#define RK8_C4 (1.0 / 8.0)
#define RK8_C5 (5.0 / 16.0)
#define RK8_C6 (3.0 / 8.0)
#define RK8_C7 (59.0 / 400.0)
#define RK8_C8 (93.0 / 200.0)
#define RK8_C9 (5490023248.0 / 9719169821.0)
#define RK8_C10 (13.0 / 20.0)
#define RK8_C11 (1201146811.0 / 1299019798.0)

/* a_ij, row by row; the zeros of the tableau are left out */
#define RK8_A21 (1.0 / 18.0)
#define RK8_A31 (1.0 / 48.0)
#define RK8_A32 (1.0 / 16.0)
#define RK8_A41 (1.0 / 32.0)
#define RK8_A43 (3.0 / 32.0)
#define RK8_A51 (5.0 / 16.0)
#define RK8_A53 (-75.0 / 64.0)
#define RK8_A54 (75.0 / 64.0)
#define RK8_A61 (3.0 / 80.0)
#define RK8_A64 (3.0 / 16.0)
#define RK8_A65 (3.0 / 20.0)
#define RK8_A71 (29443841.0 / 614563906.0)
#define RK8_A74 (77736538.0 / 692538347.0)
#define RK8_A75 (-28693883.0 / 1125000000.0)
#define RK8_A76 (23124283.0 / 1800000000.0)
#define RK8_A81 (16016141.0 / 946692911.0)
#define RK8_A84 (61564180.0 / 158732637.0)
#define RK8_A85 (22789713.0 / 633445777.0)
#define RK8_A86 (545815736.0 / 2771057229.0)
#define RK8_A87 (-180193667.0 / 1043307555.0)
#define RK8_A91 (39632708.0 / 573591083.0)
#define RK8_A94 (-433636366.0 / 683701615.0)
#define RK8_A95 (-421739975.0 / 2616292301.0)
#define RK8_A96 (100302831.0 / 723423059.0)
#define RK8_A97 (790204164.0 / 839813087.0)
#define RK8_A98 (800635310.0 / 3783071287.0)
#define RK8_A10_1 (246121993.0 / 1340847787.0)
#define RK8_A10_4 (-37695042795.0 / 15268766246.0)
#define RK8_A10_5 (-309121744.0 / 1061227803.0)
#define RK8_A10_6 (-12992083.0 / 490766935.0)
#define RK8_A10_7 (6005943493.0 / 2108947869.0)
#define RK8_A10_8 (393006217.0 / 1396673457.0)
#define RK8_A10_9 (123872331.0 / 1001029789.0)
#define RK8_A11_1 (-1028468189.0 / 846180014.0)
#define RK8_A11_4 (8478235783.0 / 508512852.0)
#define RK8_A11_5 (1311729495.0 / 1432422823.0)
#define RK8_A11_6 (-10304129995.0 / 1701304382.0)
#define RK8_A11_7 (-48777925059.0 / 3047939560.0)
#define RK8_A11_8 (15336726248.0 / 1032824649.0)
#define RK8_A11_9 (-45442868181.0 / 3398467696.0)
#define RK8_A11_10 (3065993473.0 / 597172653.0)
#define RK8_A12_1 (185892177.0 / 718116043.0)
#define RK8_A12_4 (-3185094517.0 / 667107341.0)
#define RK8_A12_5 (-477755414.0 / 1098053517.0)
#define RK8_A12_6 (-703635378.0 / 230739211.0)
#define RK8_A12_7 (5731566787.0 / 1027545527.0)
#define RK8_A12_8 (5232866602.0 / 850066563.0)
#define RK8_A12_9 (-4093664535.0 / 808688257.0)
#define RK8_A12_10 (3962137247.0 / 1805957418.0)
#define RK8_A12_11 (65686358.0 / 487910083.0)
#define RK8_A13_1 (403863854.0 / 491063109.0)
#define RK8_A13_4 (-5068492393.0 / 434740067.0)
#define RK8_A13_5 (-411421997.0 / 543043805.0)
#define RK8_A13_6 (652783627.0 / 914296604.0)
#define RK8_A13_7 (11173962825.0 / 925320556.0)
#define RK8_A13_8 (-13158990841.0 / 6184727034.0)
#define RK8_A13_9 (3936647629.0 / 1978049680.0)
#define RK8_A13_10 (-160528059.0 / 685178525.0)
#define RK8_A13_11 (248638103.0 / 1413531060.0)

/* b_i, order 8 (b_2..b_5 = 0) */
#define RK8_B1 (14005451.0 / 335480064.0)
#define RK8_B6 (-59238493.0 / 1068277825.0)
#define RK8_B7 (181606767.0 / 758867731.0)
#define RK8_B8 (561292985.0 / 797845732.0)
#define RK8_B9 (-1041891430.0 / 1371343529.0)
#define RK8_B10 (760417239.0 / 1151165299.0)
#define RK8_B11 (118820643.0 / 751138087.0)
#define RK8_B12 (-528747749.0 / 2220607170.0)
#define RK8_B13 (1.0 / 4.0)

/* bhat_i, order 7 (bhat_13 = 0) */
#define RK8_BHAT1 (13451932.0 / 455176623.0)
#define RK8_BHAT6 (-808719846.0 / 976000145.0)
#define RK8_BHAT7 (1757004468.0 / 5645159321.0)
#define RK8_BHAT8 (656045339.0 / 265891186.0)
#define RK8_BHAT9 (-3867574721.0 / 1518517206.0)
#define RK8_BHAT10 (465885868.0 / 322736535.0)
#define RK8_BHAT11 (53011238.0 / 667516719.0)
#define RK8_BHAT12 (2.0 / 45.0)

#endif
