/* mhd_baseline.c -- a bare libmicrohttpd server: the ceiling voronoid's
 * request rate is compared with.
 *
 * It runs libmicrohttpd exactly as voronoid does (internal polling thread,
 * MHD_USE_POLL, a pool of threads: 2 unless told otherwise, 16 KiB of
 * memory per connection as SRV_CONNECTION_MEMORY in server/server.c) and
 * answers every request, whatever its method, path and body, with the
 * same tiny fixed JSON body once the request body has been read and
 * dropped. The response is queued on the handler's second call or later,
 * never the first, as voronoid does (queueing on the first forces
 * "Connection: close"). The difference
 * between this server's requests per second and voronoid's on the same
 * load is what parsing, computing and writing a diagram costs.
 *
 * usage: mhd_baseline PORT [THREADS]   (127.0.0.1 only; THREADS is the
 *        size of libmicrohttpd's thread pool, 2 by default, to be given
 *        the same as voronoid's --http-threads; runs until SIGINT or
 *        SIGTERM, prints "ready PORT" once listening)
 */
#include <microhttpd.h>
#include <netinet/in.h>
#include <arpa/inet.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char body[] = "{\"ok\":true}\n";

static enum MHD_Result handle(void *cls, struct MHD_Connection *conn,
                              const char *url, const char *method,
                              const char *version, const char *upload_data,
                              size_t *upload_data_size, void **con_cls) {
    static int first_call_marker;
    struct MHD_Response *resp = cls;
    (void)url;
    (void)method;
    (void)version;
    (void)upload_data;
    if (*con_cls == NULL) { /* first call: headers only */
        *con_cls = &first_call_marker;
        return MHD_YES;
    }
    if (*upload_data_size != 0) { /* a piece of the body: drop it */
        *upload_data_size = 0;
        return MHD_YES;
    }
    return MHD_queue_response(conn, MHD_HTTP_OK, resp);
}

int main(int argc, char **argv) {
    long port = argc == 2 || argc == 3 ? strtol(argv[1], NULL, 10) : 0;
    long threads = argc == 3 ? strtol(argv[2], NULL, 10) : 2;
    if (port <= 0 || port > 65535 || threads < 1 || threads > 64) {
        fputs("usage: mhd_baseline PORT [THREADS]\n", stderr);
        return 2;
    }
    sigset_t stop;
    int sig = 0;
    sigemptyset(&stop);
    sigaddset(&stop, SIGINT);
    sigaddset(&stop, SIGTERM);
    /* Block before MHD starts its threads so that they inherit the mask and
     * only sigwait() below sees the signals. */
    pthread_sigmask(SIG_BLOCK, &stop, NULL);

    struct MHD_Response *resp = MHD_create_response_from_buffer(
        sizeof body - 1, (void *)body, MHD_RESPMEM_PERSISTENT);
    if (!resp || MHD_add_response_header(resp, "Content-Type",
                                         "application/json") != MHD_YES) {
        fputs("mhd_baseline: cannot create the response\n", stderr);
        return 1;
    }
    struct sockaddr_in addr;
    memset(&addr, 0, sizeof addr);
    addr.sin_family = AF_INET;
    addr.sin_port = htons((uint16_t)port);
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    struct MHD_Daemon *d = MHD_start_daemon(
        MHD_USE_INTERNAL_POLLING_THREAD | MHD_USE_POLL, (uint16_t)port, NULL,
        NULL, handle, resp, MHD_OPTION_THREAD_POOL_SIZE, (unsigned)threads,
        MHD_OPTION_SOCK_ADDR, (const struct sockaddr *)&addr,
        MHD_OPTION_CONNECTION_LIMIT, (unsigned)1024,
        MHD_OPTION_CONNECTION_MEMORY_LIMIT, (size_t)(16 * 1024), MHD_OPTION_END);
    if (!d) {
        fprintf(stderr, "mhd_baseline: cannot listen on 127.0.0.1:%ld\n",
                port);
        MHD_destroy_response(resp);
        return 1;
    }
    printf("ready %ld\n", port);
    fflush(stdout);
    sigwait(&stop, &sig);
    MHD_stop_daemon(d);
    MHD_destroy_response(resp);
    return 0;
}
