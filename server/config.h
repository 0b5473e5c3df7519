/* config.h -- voronoid's configuration: flags and environment, validated
 * once into an immutable struct.
 *
 * Every setting has a flag (--port 8080 or --port=8080) and an environment
 * variable (VORONOID_PORT); a flag wins over the environment, the
 * environment over the default. Values are checked here and nowhere else:
 * the rest of the server reads a const srv_config and trusts it.
 */
#ifndef VOR_SRV_CONFIG_H
#define VOR_SRV_CONFIG_H

#include <stddef.h>
#include <stdio.h>

typedef struct srv_config {
    char bind[64];              /* numeric IPv4 or IPv6 address */
    int port;                   /* 0 = ephemeral */
    int http_threads;           /* libmicrohttpd's polling threads */
    int workers;                /* compute threads */
    int queue;                  /* jobs waiting for a worker, at most */
    size_t inline_points;       /* computations of at most this many points
                                   run on the connection's thread; 0 = none */
    size_t max_body;            /* bytes */
    size_t max_points;          /* input or generated points */
    double timeout;             /* seconds from a full request to its answer */
    double grace;               /* seconds to finish in-flight work on SIGTERM */
    unsigned connection_timeout;/* seconds a connection may stay idle */
    unsigned max_connections;
    unsigned max_connections_per_ip; /* 0 = no limit per client address */
    double header_timeout;      /* seconds for a request line and headers */
    size_t min_upload_rate;     /* bytes/s a body must keep up; 0 = none */
    double send_timeout;        /* seconds an answer may wait for a client
                                   that does not read */
    double drain;               /* seconds of accepting with Connection:
                                   close after SIGTERM, before closing */
    size_t answer_memory;       /* bytes: budget of answers in flight */
    char web_dir[4096];         /* "" = the embedded page */
} srv_config;

typedef enum srv_config_result {
    SRV_CONFIG_OK,
    SRV_CONFIG_HELP,  /* --help was given: print srv_config_usage, exit 0 */
    SRV_CONFIG_ERROR  /* message in err: print it, exit 2 */
} srv_config_result;

/* Looks up an environment variable; NULL when unset. getenv fits. */
typedef const char *(*srv_getenv_fn)(const char *name);

/* Fills *out with the defaults (cpus = number of processors, used for the
 * thread counts; the answer memory comes from the machine's memory, see
 * srv_config_answer_memory_for). Cannot fail. */
void srv_config_defaults(srv_config *out, int cpus);

/* The default --answer-memory for a machine with ram bytes of memory (0 =
 * unknown): a quarter of it, at most 1 GiB, at least 64 MiB. */
size_t srv_config_answer_memory_for(unsigned long long ram);

/* Parses argv[1..argc-1] and the environment (through env, which may be
 * NULL for none) over the defaults. On SRV_CONFIG_ERROR err holds one line
 * naming the flag or variable and the offending value, and *out is
 * unspecified. Never prints, never exits. */
srv_config_result srv_config_parse(int argc, char *const *argv,
                                   srv_getenv_fn env, int cpus,
                                   srv_config *out, char *err,
                                   size_t err_size);

/* The --help text. */
void srv_config_usage(FILE *f);

/* One line per setting, "name value", for the start-up banner. */
void srv_config_print(const srv_config *c, FILE *f);

#endif /* VOR_SRV_CONFIG_H */
