/* pool.c -- the compute thread pool: bounded queue, deadlines, shutdown.
 *
 * Representation: one mutex guards everything below it in struct srv_pool:
 * a ring buffer of waiting jobs (queue_cap + workers slots, since jobs an
 * idle worker is about to take do not count against queue_cap, plus one
 * that keeps room for the exit sentinel), one slot per worker naming the job it
 * runs, and the counters. Two condition variables hang off that mutex:
 * `work` wakes workers when a job (or the sentinel) is queued; `watch` wakes
 * the deadline timer when an earlier deadline arrives or on shutdown, and
 * srv_pool_free when the pool may have become idle. (libuv's pool needs one;
 * the timer's timed wait is why this one has a second, so a worker's
 * wake-up is never spent on the timer.) A finished job wakes nobody unless
 * srv_pool_free is waiting: the timer, if it was sleeping until that job's
 * deadline, wakes then, finds nothing due and sleeps on -- one spurious
 * wake-up per deadline instead of one per job.
 *
 * Job states, changed only under the mutex:
 *
 *     QUEUED --worker--> RUNNING --run() returns--> FINISHED
 *        |                  |
 *        | deadline/cancel  | deadline/cancel: done() now, result discarded
 *        v                  v
 *     DROPPED            ABANDONED --run() returns--> FINISHED
 *
 * Whoever moves a job out of QUEUED or RUNNING into a state that settles its
 * outcome calls done() exactly once, after unlocking; release() follows
 * once the pool holds no pointer to the job.
 *
 * Lock order: the pool mutex is a leaf. No other lock is taken while it is
 * held and no callback runs under it, so callbacks may take their own locks
 * (libmicrohttpd's, the metrics') and call srv_pool_submit.
 *
 * Shutdown: the sentinel job sits at the head of the queue and is never
 * popped; a worker that sees it exits, and the next one sees it too.
 *
 * Cost: submit O(1); the timer scans queue + workers (O(queue_cap)) when a
 * deadline passes or an earlier one arrives, not per job otherwise.
 */
#include "pool.h"

#include <errno.h>
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum { JOB_QUEUED = 1, JOB_RUNNING, JOB_ABANDONED, JOB_FINISHED, JOB_DROPPED };

struct srv_pool {
    pthread_mutex_t mu;
    pthread_cond_t work;  /* workers: a job or the sentinel was queued */
    pthread_cond_t watch; /* timer and srv_pool_free: state changed */

    srv_job **ring;       /* queue_cap + 1 slots */
    size_t ring_size, head, n_queued, queue_cap;
    srv_job **running;    /* one slot per worker, NULL when idle */
    size_t n_running;
    int n_workers;
    int closed;           /* no more submissions */
    int idle_waiters;     /* srv_pool_free calls waiting on watch for idle */
    int stopping;         /* the timer exits */
    int64_t timer_target; /* the deadline the timer sleeps until */
    srv_job sentinel;

    pthread_t *threads;   /* n_workers workers, then the timer */
    int n_threads;

    /* Room to settle every job at once (every ring slot and every
     * worker): one set for the timer thread, one for srv_pool_cancel_all. */
    srv_job **timer_jobs, **cancel_jobs;
    int *timer_rel, *cancel_rel;
};

struct worker_arg {
    srv_pool *pool;
    size_t slot;
};

int64_t srv_now_ns(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

static struct timespec to_timespec(int64_t ns) {
    struct timespec ts;
    ts.tv_sec = (time_t)(ns / 1000000000);
    ts.tv_nsec = (long)(ns % 1000000000);
    return ts;
}

int srv_job_abandoned(srv_job *job) {
    return atomic_load_explicit(&job->abandoned, memory_order_acquire);
}

static srv_job *ring_at(const srv_pool *p, size_t i) {
    return p->ring[(p->head + i) % p->ring_size];
}

static void ring_push(srv_pool *p, srv_job *job) {
    p->ring[(p->head + p->n_queued) % p->ring_size] = job;
    p->n_queued++;
}

/* Removes queued entry i, keeping the order of the rest. */
static void ring_remove(srv_pool *p, size_t i) {
    for (size_t k = i; k + 1 < p->n_queued; k++)
        p->ring[(p->head + k) % p->ring_size] =
            p->ring[(p->head + k + 1) % p->ring_size];
    p->n_queued--;
}

/* A list of jobs whose callbacks are to be called after unlocking. */
typedef struct settle_list {
    srv_job **job;
    int *release; /* also release (the job left the pool entirely) */
    size_t n;
} settle_list;

static void settle(settle_list *l, srv_job_outcome outcome) {
    for (size_t i = 0; i < l->n; i++) {
        srv_job *job = l->job[i];
        int rel = l->release[i];
        job->done(job, outcome);
        if (rel) job->release(job);
    }
    l->n = 0;
}

/* Moves jobs whose deadline is <= now (all jobs when now < 0) out of the
 * queue and running slots into l (sized ring_size + workers). Under mu. */
static void collect(srv_pool *p, int64_t now, settle_list *l) {
    for (size_t i = 0; i < p->n_queued;) {
        srv_job *job = ring_at(p, i);
        if (job != &p->sentinel &&
            (now < 0 || (job->deadline_ns != 0 && job->deadline_ns <= now))) {
            ring_remove(p, i);
            job->state = JOB_DROPPED;
            atomic_store_explicit(&job->abandoned, 1, memory_order_release);
            l->job[l->n] = job;
            l->release[l->n] = 1;
            l->n++;
        } else {
            i++;
        }
    }
    for (int w = 0; w < p->n_workers; w++) {
        srv_job *job = p->running[w];
        if (job != NULL && job->state == JOB_RUNNING &&
            (now < 0 || (job->deadline_ns != 0 && job->deadline_ns <= now))) {
            job->state = JOB_ABANDONED;
            atomic_store_explicit(&job->abandoned, 1, memory_order_release);
            l->job[l->n] = job;
            l->release[l->n] = 0;
            l->n++;
        }
    }
}

static void *worker_main(void *argp) {
    struct worker_arg *arg = argp;
    srv_pool *p = arg->pool;
    size_t slot = arg->slot;
    free(arg);

    pthread_mutex_lock(&p->mu);
    for (;;) {
        while (p->n_queued == 0) pthread_cond_wait(&p->work, &p->mu);
        srv_job *job = ring_at(p, 0);
        if (job == &p->sentinel) {
            /* Leave it for the other workers. */
            pthread_cond_signal(&p->work);
            break;
        }
        p->head = (p->head + 1) % p->ring_size;
        p->n_queued--;
        job->state = JOB_RUNNING;
        job->started_ns = srv_now_ns();
        p->running[slot] = job;
        p->n_running++;
        pthread_mutex_unlock(&p->mu);

        job->run(job);

        int64_t end = srv_now_ns();
        pthread_mutex_lock(&p->mu);
        p->running[slot] = NULL;
        p->n_running--;
        int call_done = job->state == JOB_RUNNING;
        job->state = JOB_FINISHED;
        if (p->idle_waiters > 0) pthread_cond_broadcast(&p->watch);
        pthread_mutex_unlock(&p->mu);

        if (call_done) {
            /* A deadline that passed while run() was busy and the timer has
             * not acted on yet still counts: the answer is late. */
            int late = job->deadline_ns != 0 && end > job->deadline_ns;
            if (late)
                atomic_store_explicit(&job->abandoned, 1,
                                      memory_order_release);
            job->done(job, late ? SRV_JOB_EXPIRED : SRV_JOB_RAN);
        }
        job->release(job);
        pthread_mutex_lock(&p->mu);
    }
    pthread_mutex_unlock(&p->mu);
    return NULL;
}

static void *timer_main(void *argp) {
    srv_pool *p = argp;
    settle_list l = {p->timer_jobs, p->timer_rel, 0};

    pthread_mutex_lock(&p->mu);
    while (!p->stopping) {
        collect(p, srv_now_ns(), &l);
        if (l.n > 0) {
            /* Dropped queued jobs may have left the pool idle. */
            if (p->idle_waiters > 0) pthread_cond_broadcast(&p->watch);
            pthread_mutex_unlock(&p->mu);
            settle(&l, SRV_JOB_EXPIRED);
            pthread_mutex_lock(&p->mu);
            continue;
        }
        int64_t next = INT64_MAX;
        for (size_t i = 0; i < p->n_queued; i++) {
            srv_job *job = ring_at(p, i);
            if (job != &p->sentinel && job->deadline_ns != 0 &&
                job->deadline_ns < next)
                next = job->deadline_ns;
        }
        for (int w = 0; w < p->n_workers; w++) {
            srv_job *job = p->running[w];
            if (job != NULL && job->state == JOB_RUNNING &&
                job->deadline_ns != 0 && job->deadline_ns < next)
                next = job->deadline_ns;
        }
        p->timer_target = next;
        if (next == INT64_MAX) {
            pthread_cond_wait(&p->watch, &p->mu);
        } else {
            struct timespec ts = to_timespec(next);
            pthread_cond_timedwait(&p->watch, &p->mu, &ts);
        }
    }
    pthread_mutex_unlock(&p->mu);
    return NULL;
}

static void free_arrays(srv_pool *p) {
    free(p->ring);
    free(p->running);
    free(p->threads);
    free(p->timer_jobs);
    free(p->cancel_jobs);
    free(p->timer_rel);
    free(p->cancel_rel);
    free(p);
}

srv_pool *srv_pool_new(int workers, int queue_cap) {
    if (workers < 1) workers = 1;
    if (queue_cap < 1) queue_cap = 1;
    srv_pool *p = calloc(1, sizeof *p);
    if (p == NULL) return NULL;
    p->queue_cap = (size_t)queue_cap;
    p->ring_size = p->queue_cap + (size_t)workers + 1;
    p->n_workers = workers;
    p->timer_target = INT64_MAX;
    p->ring = calloc(p->ring_size, sizeof *p->ring);
    p->running = calloc((size_t)workers, sizeof *p->running);
    p->threads = calloc((size_t)workers + 1, sizeof *p->threads);
    size_t settle_cap = p->ring_size + (size_t)workers; /* queued + running */
    p->timer_jobs = calloc(settle_cap, sizeof *p->timer_jobs);
    p->cancel_jobs = calloc(settle_cap, sizeof *p->cancel_jobs);
    p->timer_rel = calloc(settle_cap, sizeof *p->timer_rel);
    p->cancel_rel = calloc(settle_cap, sizeof *p->cancel_rel);
    if (p->ring == NULL || p->running == NULL || p->threads == NULL ||
        p->timer_jobs == NULL || p->cancel_jobs == NULL ||
        p->timer_rel == NULL || p->cancel_rel == NULL)
        goto fail_alloc;

    pthread_condattr_t ca;
    if (pthread_mutex_init(&p->mu, NULL) != 0) goto fail_alloc;
    if (pthread_condattr_init(&ca) != 0) goto fail_mu;
    pthread_condattr_setclock(&ca, CLOCK_MONOTONIC);
    if (pthread_cond_init(&p->work, &ca) != 0) {
        pthread_condattr_destroy(&ca);
        goto fail_mu;
    }
    if (pthread_cond_init(&p->watch, &ca) != 0) {
        pthread_condattr_destroy(&ca);
        pthread_cond_destroy(&p->work);
        goto fail_mu;
    }
    pthread_condattr_destroy(&ca);

    for (int w = 0; w < workers; w++) {
        struct worker_arg *arg = malloc(sizeof *arg);
        if (arg == NULL) goto fail_threads;
        arg->pool = p;
        arg->slot = (size_t)w;
        if (pthread_create(&p->threads[p->n_threads], NULL, worker_main,
                           arg) != 0) {
            free(arg);
            goto fail_threads;
        }
        p->n_threads++;
    }
    if (pthread_create(&p->threads[p->n_threads], NULL, timer_main, p) != 0)
        goto fail_threads;
    p->n_threads++;
    return p;

fail_threads:
    /* Only workers can be running here: stop them with the sentinel. */
    pthread_mutex_lock(&p->mu);
    ring_push(p, &p->sentinel);
    pthread_cond_broadcast(&p->work);
    pthread_mutex_unlock(&p->mu);
    for (int t = 0; t < p->n_threads; t++) pthread_join(p->threads[t], NULL);
    pthread_cond_destroy(&p->work);
    pthread_cond_destroy(&p->watch);
fail_mu:
    pthread_mutex_destroy(&p->mu);
fail_alloc:
    free_arrays(p);
    return NULL;
}

int srv_pool_submit(srv_pool *p, srv_job *job) {
    pthread_mutex_lock(&p->mu);
    if (p->closed) {
        pthread_mutex_unlock(&p->mu);
        return SRV_POOL_CLOSED;
    }
    /* Jobs an idle worker is about to take do not count as waiting: a
     * queue of q behind w workers holds q + w jobs however fast the
     * workers wake up. */
    size_t idle = (size_t)p->n_workers - p->n_running;
    if (p->n_queued >= p->queue_cap + idle) {
        pthread_mutex_unlock(&p->mu);
        return SRV_POOL_FULL;
    }
    job->state = JOB_QUEUED;
    atomic_store_explicit(&job->abandoned, 0, memory_order_relaxed);
    job->queued_ns = srv_now_ns();
    job->started_ns = 0;
    ring_push(p, job);
    pthread_cond_signal(&p->work);
    /* Wake the timer only if this deadline is earlier than its alarm. */
    if (job->deadline_ns != 0 && job->deadline_ns < p->timer_target) {
        p->timer_target = job->deadline_ns;
        pthread_cond_broadcast(&p->watch);
    }
    pthread_mutex_unlock(&p->mu);
    return SRV_POOL_OK;
}

void srv_pool_stats(srv_pool *p, size_t *queued, size_t *running) {
    pthread_mutex_lock(&p->mu);
    size_t q = p->n_queued;
    if (q > 0 && ring_at(p, 0) == &p->sentinel) q--;
    if (queued) *queued = q;
    if (running) *running = p->n_running;
    pthread_mutex_unlock(&p->mu);
}

void srv_pool_close(srv_pool *p) {
    pthread_mutex_lock(&p->mu);
    p->closed = 1;
    pthread_mutex_unlock(&p->mu);
}

void srv_pool_cancel_all(srv_pool *p) {
    settle_list l = {p->cancel_jobs, p->cancel_rel, 0};
    pthread_mutex_lock(&p->mu);
    collect(p, -1, &l);
    pthread_cond_broadcast(&p->watch);
    pthread_mutex_unlock(&p->mu);
    settle(&l, SRV_JOB_CANCELLED);
}

int srv_pool_free(srv_pool *p, double wait_s) {
    if (p == NULL) return 0;
    if (wait_s < 0) wait_s = 0;
    int64_t until = srv_now_ns() + (int64_t)(wait_s * 1e9);
    struct timespec ts = to_timespec(until);

    pthread_mutex_lock(&p->mu);
    p->closed = 1;
    p->idle_waiters++;
    while (p->n_queued + p->n_running > 0) {
        int rc = pthread_cond_timedwait(&p->watch, &p->mu, &ts);
        if (rc == ETIMEDOUT) break;
    }
    p->idle_waiters--;
    if (p->n_queued + p->n_running > 0) {
        pthread_mutex_unlock(&p->mu);
        return -1;
    }
    ring_push(p, &p->sentinel);
    p->stopping = 1;
    pthread_cond_broadcast(&p->work);
    pthread_cond_broadcast(&p->watch);
    pthread_mutex_unlock(&p->mu);

    for (int t = 0; t < p->n_threads; t++) pthread_join(p->threads[t], NULL);
    pthread_cond_destroy(&p->work);
    pthread_cond_destroy(&p->watch);
    pthread_mutex_destroy(&p->mu);
    free_arrays(p);
    return 0;
}
