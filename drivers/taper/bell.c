/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * bell.c -- a doorbell for rank 0 of an MPI sweep (bell.h).
 *
 * The handshake: rank r connects, sends the job's token and r (12 bytes);
 * rank 0 checks them and answers one byte.  A rank rings only once it has
 * that answer, and rank 0 counts the rings only of the ranks it answered,
 * so that both sides agree on who rings.  Everything has a deadline: a
 * rank that cannot reach rank 0 in time goes without a bell.
 */
#define _DEFAULT_SOURCE /* getifaddrs' IFF_ flags, SOCK_CLOEXEC */
#include "bell.h"

#include <errno.h>
#include <fcntl.h>
#include <ifaddrs.h>
#include <net/if.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/random.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

enum { HELLO = 12, ACK = 0x5a };

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int ms_until(double deadline)
{
    double left = deadline - now();
    return left > 0 ? (int)(left * 1e3) + 1 : 0;
}

int bell_listen(bell_address *a)
{
    memset(a, 0, sizeof *a);
    if (getrandom(&a->token, sizeof a->token, 0) != (ssize_t)sizeof a->token)
        a->token = (uint64_t)time(NULL) * 6364136223846793005ull ^ (uint64_t)getpid();
    gethostname(a->host, sizeof a->host - 1);
    int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) return -1;
    struct sockaddr_in sin = {.sin_family = AF_INET, .sin_addr.s_addr = htonl(INADDR_ANY)};
    socklen_t len = sizeof sin;
    if (bind(fd, (struct sockaddr *)&sin, sizeof sin) != 0 || listen(fd, SOMAXCONN) != 0 ||
        getsockname(fd, (struct sockaddr *)&sin, &len) != 0) {
        close(fd);
        return -1;
    }
    a->port = sin.sin_port;
    /* Loopback first: the ranks on this host. */
    struct ifaddrs *list = NULL;
    if (getifaddrs(&list) != 0) list = NULL;
    for (int loop = 1; loop >= 0; loop--)
        for (struct ifaddrs *i = list; i && a->n < BELL_MAX_ADDRESSES; i = i->ifa_next) {
            if (!i->ifa_addr || i->ifa_addr->sa_family != AF_INET || !(i->ifa_flags & IFF_UP))
                continue;
            if (!(i->ifa_flags & IFF_LOOPBACK) != !loop) continue;
            a->ipv4[a->n++] = ((const struct sockaddr_in *)i->ifa_addr)->sin_addr.s_addr;
        }
    if (list) freeifaddrs(list);
    if (a->n == 0) {
        close(fd);
        return -1;
    }
    return fd;
}

/* Reads exactly n bytes before the deadline. */
static int read_all(int fd, void *buf, size_t n, double deadline)
{
    size_t got = 0;
    while (got < n) {
        struct pollfd p = {.fd = fd, .events = POLLIN};
        int ms = ms_until(deadline);
        if (ms == 0 || poll(&p, 1, ms) <= 0) return -1;
        ssize_t k = read(fd, (char *)buf + got, n - got);
        if (k <= 0) return -1;
        got += (size_t)k;
    }
    return 0;
}

int bell_accept(int listener, const bell_address *a, int ranks, double seconds, int *fd)
{
    for (int r = 0; r < ranks; r++) fd[r] = -1;
    int connected = 0;
    double deadline = now() + seconds;
    while (listener >= 0 && connected < ranks - 1) {
        struct pollfd p = {.fd = listener, .events = POLLIN};
        int ms = ms_until(deadline);
        if (ms == 0 || poll(&p, 1, ms) <= 0) break;
        int c = accept(listener, NULL, NULL);
        if (c < 0) continue;
        fcntl(c, F_SETFD, FD_CLOEXEC);
        unsigned char hello[HELLO];
        uint64_t token;
        uint32_t r;
        int ok = read_all(c, hello, sizeof hello, now() + 2.0) == 0;
        memcpy(&token, hello, sizeof token);
        memcpy(&r, hello + 8, sizeof r);
        unsigned char ack = ACK;
        if (ok && token == a->token && r > 0 && r < (uint32_t)ranks && fd[r] < 0 &&
            write(c, &ack, 1) == 1) {
            fd[r] = c;
            connected++;
        } else {
            close(c);
        }
    }
    if (listener >= 0) close(listener);
    return connected;
}

/* A connection to addr:port within the deadline, or -1. */
static int connect_by(uint32_t addr, uint16_t port, double deadline)
{
    int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    if (fd < 0) return -1;
    struct sockaddr_in sin = {.sin_family = AF_INET, .sin_port = port, .sin_addr.s_addr = addr};
    if (connect(fd, (struct sockaddr *)&sin, sizeof sin) != 0) {
        struct pollfd p = {.fd = fd, .events = POLLOUT};
        int err = 0;
        socklen_t len = sizeof err;
        int ms = ms_until(deadline);
        if (errno != EINPROGRESS || ms == 0 || poll(&p, 1, ms) <= 0 ||
            getsockopt(fd, SOL_SOCKET, SO_ERROR, &err, &len) != 0 || err != 0) {
            close(fd);
            return -1;
        }
    }
    int flags = fcntl(fd, F_GETFL);
    fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
    int one = 1; /* a ring is one byte, to be sent at once */
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    return fd;
}

int bell_connect(const bell_address *a, int rank, double seconds)
{
    double deadline = now() + seconds;
    char host[sizeof a->host] = "";
    gethostname(host, sizeof host - 1);
    int same_host = strncmp(host, a->host, sizeof host) == 0;
    for (unsigned k = 0; k < a->n && k < BELL_MAX_ADDRESSES; k++) {
        if (ntohl(a->ipv4[k]) >> 24 == 127 && !same_host) continue; /* rank 0's loopback */
        double until = now() + 2.0 < deadline ? now() + 2.0 : deadline;
        int fd = connect_by(a->ipv4[k], a->port, until);
        if (fd < 0) continue;
        unsigned char hello[HELLO], ack = 0;
        uint32_t r = (uint32_t)rank;
        memcpy(hello, &a->token, sizeof a->token);
        memcpy(hello + 8, &r, sizeof r);
        if (send(fd, hello, sizeof hello, MSG_NOSIGNAL) == (ssize_t)sizeof hello &&
            read_all(fd, &ack, 1, deadline) == 0 && ack == ACK)
            return fd;
        close(fd);
    }
    return -1;
}

void bell_ring(int fd, char ring)
{
    if (fd >= 0) (void)!send(fd, &ring, 1, MSG_NOSIGNAL);
}

int bell_await(int fd, int timeout_ms)
{
    struct pollfd p = {.fd = fd, .events = POLLIN};
    int n = poll(&p, 1, timeout_ms);
    if (n < 0) return errno == EINTR ? 0 : -1;
    if (n == 0) return 0;
    char ring;
    ssize_t k = read(fd, &ring, 1);
    if (k == 1) return ring;
    return k < 0 && errno == EINTR ? 0 : -1;
}

void bell_wait(int *fd, int ranks, int timeout_ms, unsigned long *rung)
{
    struct pollfd stack[64], *p = ranks <= 64 ? stack : calloc((size_t)ranks, sizeof *p);
    if (!p) { /* out of memory: a short nap instead */
        struct timespec ms = {0, 1000000L};
        nanosleep(&ms, NULL);
        return;
    }
    for (int r = 0; r < ranks; r++) p[r] = (struct pollfd){.fd = fd[r], .events = POLLIN};
    if (poll(p, (nfds_t)ranks, timeout_ms) > 0) {
        for (int r = 0; r < ranks; r++) {
            if (fd[r] < 0 || !(p[r].revents & (POLLIN | POLLHUP | POLLERR))) continue;
            char buf[256];
            ssize_t k = read(fd[r], buf, sizeof buf);
            if (k > 0) {
                rung[r] += (unsigned long)k;
            } else if (k == 0 || (errno != EINTR && errno != EAGAIN)) {
                close(fd[r]); /* that rank has ended */
                fd[r] = -1;
            }
        }
    }
    if (p != stack) free(p);
}
