/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * bell.h -- doorbells for the ranks of an MPI sweep: a TCP connection
 * between rank 0 and each other rank, on which a rank writes one byte
 * before (a worker) or after (rank 0) each message it sends the other, so
 * that the other can sleep in poll() until a message comes.  Rank 0 waits
 * for requests and results, a worker for the answer to its request and,
 * at the end, for rank 0 to be done.
 *
 * Why not MPI itself: a blocking MPI_Recv or MPI_Probe does not sleep in
 * Open MPI, it spins, keeping a core busy all the time it waits, and MPI
 * has no call that waits for a message and for anything else at once.  The bell carries no data: the messages stay MPI
 * messages, and a rank whose bell cannot be set up (no TCP route to rank
 * 0) is served by polling instead (drivers/taper/sweep_mpi.c).
 *
 * Not part of libtaper: compiled into the taper executable with MPI only.
 */
#ifndef TAPER_BELL_H
#define TAPER_BELL_H

#include <stdint.h>

enum { BELL_MAX_ADDRESSES = 16 };

/* Where the other ranks ring: rank 0 fills it, MPI broadcasts its bytes. */
typedef struct bell_address {
    uint64_t token;                       /* proves a caller is of this job */
    uint32_t ipv4[BELL_MAX_ADDRESSES];    /* rank 0's addresses, network order */
    uint16_t port;                        /* network order                   */
    uint16_t n;                           /* addresses in ipv4               */
    char host[64];                        /* rank 0's host name              */
} bell_address;

/* Rank 0: a listening socket on every interface; fills *a.  The socket, or
 * -1 (no bells: the other ranks are polled). */
int bell_listen(bell_address *a);

/* Rank 0: accepts the other ranks' bells (ranks 1 .. ranks-1) for
 * `seconds` at most, or until every one has rung in; fd[r] = rank r's
 * connection, -1 for those that did not.  Closes the listening socket.
 * Returns the number of ranks connected. */
int bell_accept(int listener, const bell_address *a, int ranks, double seconds, int *fd);

/* Rank `rank` > 0: connects to rank 0's bell and waits for it to answer,
 * `seconds` at most.  The connection, or -1. */
int bell_connect(const bell_address *a, int rank, double seconds);

enum { BELL_MESSAGE = 1, BELL_FAREWELL = 2 };

/* Rings once: BELL_MESSAGE for a message, BELL_FAREWELL when rank 0 is
 * done. */
void bell_ring(int fd, char ring);

/* A worker: sleeps until a ring or timeout_ms (-1: no limit).  The ring,
 * 0 after the timeout, -1 if the connection has ended. */
int bell_await(int fd, int timeout_ms);

/* Rank 0: sleeps until a bell rings or timeout_ms pass (-1: no limit);
 * adds to rung[r] the rings of rank r.  A connection that ends is closed
 * and set to -1. */
void bell_wait(int *fd, int ranks, int timeout_ms, unsigned long *rung);

#endif
