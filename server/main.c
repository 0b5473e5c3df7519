/* main.c -- voronoid's entry point: configuration, signals, shutdown.
 *
 * SIGTERM and SIGINT are blocked before any thread starts, so only the main
 * thread receives them (sigwait). On the first one: /readyz turns 503 and
 * answers say Connection: close while the daemon keeps accepting for
 * --drain seconds (so that load balancers notice before connections are
 * refused); then it stops listening without resetting what the kernel had
 * queued, waits up to --grace for in-flight requests, answers what is left
 * with 503, stops, exits 0. A second signal cuts drain and grace short.
 *
 * The allocator is told once, before any thread starts, to keep up to
 * 16 MiB of free memory per arena rather than give it back to the system
 * after every request, and to map blocks of their own only from 4 MiB up.
 * By default glibc trims a thread's heap once 128 KiB lie free at its top
 * and maps every block from 128 KiB until its adaptive threshold has seen
 * big ones, so each small request paid for madvise() and the page faults
 * of memory it had just returned (about a tenth of its time); large
 * requests still return their memory. Fast bins are turned off: a small
 * request frees more small blocks than the thread cache keeps (the
 * libmicrohttpd response headers, allocated with calloc, which bypasses
 * that cache), so they piled up in fast bins that the answer's first
 * block of over 1 KiB then had to consolidate: about 950 instructions of
 * a 10-point request's 122,000, against 400 more in free() without them.
 */
#include <malloc.h>
#include <time.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "config.h"
#include "server.h"

static const char *env_lookup(const char *name) { return getenv(name); }

/* A SIGTERM or SIGINT arrived (SIGHUP does not count); does not wait. */
static int second_signal(const sigset_t *sigs) {
    struct timespec zero = {0, 0};
    int sig = sigtimedwait(sigs, NULL, &zero);
    return sig == SIGTERM || sig == SIGINT;
}

int main(int argc, char **argv) {
    srv_config cfg;
    char err[512];
    long cpus = sysconf(_SC_NPROCESSORS_ONLN);

    switch (srv_config_parse(argc, argv, env_lookup, cpus > 0 ? (int)cpus : 1,
                             &cfg, err, sizeof err)) {
    case SRV_CONFIG_HELP:
        srv_config_usage(stdout);
        return 0;
    case SRV_CONFIG_ERROR:
        fprintf(stderr, "voronoid: %s\n", err);
        return 2;
    case SRV_CONFIG_OK:
        break;
    }

#if defined(M_TRIM_THRESHOLD) && defined(M_MMAP_THRESHOLD)
    mallopt(M_MMAP_THRESHOLD, 4 << 20);
    mallopt(M_TRIM_THRESHOLD, 16 << 20);
#endif
#if defined(M_MXFAST)
    mallopt(M_MXFAST, 0);
#endif

    sigset_t sigs;
    sigemptyset(&sigs);
    sigaddset(&sigs, SIGTERM);
    sigaddset(&sigs, SIGINT);
    sigaddset(&sigs, SIGHUP);
    pthread_sigmask(SIG_BLOCK, &sigs, NULL);
    signal(SIGPIPE, SIG_IGN);

    setvbuf(stderr, NULL, _IOLBF, 0);
    srv_config_print(&cfg, stderr);
    srv_server *s = srv_server_new(&cfg, STDERR_FILENO, err, sizeof err);
    if (s == NULL) {
        fprintf(stderr, "voronoid: %s\n", err);
        return 1;
    }
    int ipv6 = strchr(cfg.bind, ':') != NULL;
    fprintf(stderr, "voronoid: listening on http://%s%s%s:%d/\n",
            ipv6 ? "[" : "", cfg.bind, ipv6 ? "]" : "", srv_server_port(s));

    /* SIGHUP, which supervisors send to have a daemon reload, would end
     * the process by default; there is nothing to reload (settings are
     * read once, the log is stderr), so it is noted and ignored. */
    int sig = 0;
    while (sigwait(&sigs, &sig) == 0 && sig == SIGHUP) {
        srv_server_flush_log(s);
        fprintf(stderr, "voronoid: SIGHUP: nothing to reload, ignored\n");
    }
    srv_server_drain(s);
    srv_server_flush_log(s);
    fprintf(stderr, "voronoid: %s: draining: /readyz says 503, still "
            "accepting for %g s\n", sig == SIGINT ? "SIGINT" : "SIGTERM",
            cfg.drain);

    /* Keep accepting for --drain seconds, watching for a second signal. */
    int hurry = 0;
    for (double waited = 0; waited < cfg.drain && !hurry; waited += 0.05) {
        struct timespec nap = {0, 50 * 1000 * 1000};
        nanosleep(&nap, NULL);
        hurry = second_signal(&sigs);
    }
    srv_server_stop_listening(s);
    srv_server_flush_log(s);
    fprintf(stderr, "voronoid: stopped listening (%zu connection(s) taken "
            "from the queue); finishing %zu request(s), grace %g s\n",
            srv_server_accepted_late(s), srv_server_in_flight(s),
            hurry ? 0.0 : cfg.grace);
    if (hurry) {
        fprintf(stderr, "voronoid: second signal: not waiting longer\n");
    }

    /* Wait for in-flight requests, watching for a second signal. */
    double waited = 0;
    while (!hurry && srv_server_wait_idle(s, 0.05) != 0 &&
           waited < cfg.grace) {
        waited += 0.05;
        if (second_signal(&sigs)) {
            srv_server_flush_log(s);
            fprintf(stderr, "voronoid: second signal: not waiting longer\n");
            break;
        }
    }
    if (srv_server_in_flight(s) > 0) {
        srv_server_flush_log(s);
        fprintf(stderr, "voronoid: grace over: answering %zu request(s) "
                "with 503\n", srv_server_in_flight(s));
        srv_server_cancel(s);
        srv_server_wait_idle(s, 2.0);
    }
    if (srv_server_free(s) != 0) {
        fprintf(stderr, "voronoid: stopped (a computation was still "
                "running)\n");
        fflush(stderr);
        _exit(0);
    }
    fprintf(stderr, "voronoid: stopped\n");
    return 0;
}
