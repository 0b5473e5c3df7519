/* pool.h -- a fixed pool of compute threads with a bounded queue and
 * per-job deadlines.
 *
 * A job is a caller-owned struct that embeds srv_job. The pool calls
 * job->run(job) on a worker thread, and job->done(job, outcome) exactly once
 * for every job it accepted:
 *
 *   SRV_JOB_RAN        run() returned before the deadline; called on the
 *                      worker right after run().
 *   SRV_JOB_EXPIRED    the deadline passed first: a queued job is dropped
 *                      without running; for a running job done() is called
 *                      at the deadline, from the timer thread, and whatever
 *                      run() produces afterwards is to be discarded (run()
 *                      sees srv_job_abandoned and stops early).
 *   SRV_JOB_CANCELLED  srv_pool_cancel_all() (shutdown): like EXPIRED.
 *
 * After done() the pool may still be running run() (EXPIRED, CANCELLED);
 * job->release(job) is called once the pool no longer touches the job at
 * all, and is the place to free it (or drop a reference). run() can poll
 * srv_job_abandoned() between stages to stop early.
 *
 * done() and release() are called without the pool's lock held; they may
 * call back into the pool except srv_pool_free.
 */
#ifndef VOR_SRV_POOL_H
#define VOR_SRV_POOL_H

#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>

typedef enum srv_job_outcome {
    SRV_JOB_RAN,
    SRV_JOB_EXPIRED,
    SRV_JOB_CANCELLED
} srv_job_outcome;

typedef struct srv_job srv_job;
struct srv_job {
    void (*run)(srv_job *job);
    void (*done)(srv_job *job, srv_job_outcome outcome);
    void (*release)(srv_job *job);
    int64_t deadline_ns; /* CLOCK_MONOTONIC; 0 = none */

    /* Private to the pool. */
    int state;
    atomic_int abandoned;
    int64_t queued_ns, started_ns;
};

typedef struct srv_pool srv_pool;

enum { SRV_POOL_OK = 0, SRV_POOL_FULL = 1, SRV_POOL_CLOSED = 2,
       SRV_POOL_NOMEM = 3 };

/* Starts `workers` compute threads and one deadline timer; at most
 * `queue_cap` jobs wait while every worker is busy (so queue_cap + workers
 * jobs are accepted at once). Both are clamped to at least 1.
 * NULL if memory or threads cannot be had (nothing is left running). */
srv_pool *srv_pool_new(int workers, int queue_cap);

/* Queues job (its run, done, release and deadline_ns set by the caller).
 * SRV_POOL_OK: the pool owns the job until release(). SRV_POOL_FULL (queue
 * at capacity) or SRV_POOL_CLOSED (shut down): the job was not accepted and
 * none of its callbacks will be called. */
int srv_pool_submit(srv_pool *p, srv_job *job);

/* Non-zero once the job's done() has been called with EXPIRED or
 * CANCELLED: its result will be thrown away. Any thread. */
int srv_job_abandoned(srv_job *job);

/* Monotonic clock in nanoseconds (the clock of deadline_ns). */
int64_t srv_now_ns(void);

/* Gauges: jobs waiting, jobs running. */
void srv_pool_stats(srv_pool *p, size_t *queued, size_t *running);

/* Refuses submissions from now on (SRV_POOL_CLOSED); queued and running
 * jobs go on. */
void srv_pool_close(srv_pool *p);

/* Calls done(CANCELLED) for every queued and running job that has not had
 * its done() yet; queued ones are dropped. The pool keeps working. One
 * thread at a time (it uses a settle list preallocated in the pool). */
void srv_pool_cancel_all(srv_pool *p);

/* Stops accepting, waits up to wait_s seconds for queued and running jobs
 * to finish, then tells the threads to exit (a sentinel in the queue) and
 * joins them. Returns 0 when everything was joined and freed; -1 when a
 * run() was still going after wait_s + the time given to the sentinel: the
 * pool is then left alive (threads detached, memory not freed) so that the
 * process can exit without waiting for a job that does not stop (the
 * compute jobs stop soon after they are abandoned).
 * NULL is a no-op returning 0. */
int srv_pool_free(srv_pool *p, double wait_s);

#endif /* VOR_SRV_POOL_H */
