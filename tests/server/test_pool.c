/* test_pool.c -- the compute pool: jobs run, the bounded queue refuses the
 * overflow, deadlines expire queued and running jobs, cancel_all settles
 * everything, shutdown joins; done() is called exactly once per accepted
 * job and release() after it. Jobs block on gates the test opens, so no
 * assertion depends on timing (waits have a generous hang guard only). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <pthread.h>
#include <string.h>
#include <time.h>
#include <cmocka.h>

#include "../../server/pool.h"

typedef struct tjob {
    srv_job base;
    pthread_mutex_t *mu;
    pthread_cond_t *cv;
    int *gate;        /* run() waits until *gate != 0 */
    int started, ran, done_calls, released, saw_abandoned;
    srv_job_outcome outcome;
    int order;        /* position at which run() started */
} tjob;

static pthread_mutex_t mu = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t cv = PTHREAD_COND_INITIALIZER;
static int run_counter;

static void t_run(srv_job *b) {
    tjob *j = (tjob *)b;
    pthread_mutex_lock(j->mu);
    j->started = 1;
    j->order = run_counter++;
    pthread_cond_broadcast(j->cv);
    while (j->gate != NULL && !*j->gate) pthread_cond_wait(j->cv, j->mu);
    j->ran = 1;
    pthread_mutex_unlock(j->mu);
    int ab = srv_job_abandoned(b);
    pthread_mutex_lock(j->mu);
    j->saw_abandoned = ab;
    pthread_mutex_unlock(j->mu);
}

static void t_done(srv_job *b, srv_job_outcome o) {
    tjob *j = (tjob *)b;
    pthread_mutex_lock(j->mu);
    j->done_calls++;
    j->outcome = o;
    pthread_cond_broadcast(j->cv);
    pthread_mutex_unlock(j->mu);
}

static void t_release(srv_job *b) {
    tjob *j = (tjob *)b;
    pthread_mutex_lock(j->mu);
    /* release comes after done, once. */
    assert_int_equal(j->done_calls, 1);
    j->released++;
    pthread_cond_broadcast(j->cv);
    pthread_mutex_unlock(j->mu);
}

static void init_job(tjob *j, int *gate, int64_t deadline) {
    memset(j, 0, sizeof *j);
    j->base.run = t_run;
    j->base.done = t_done;
    j->base.release = t_release;
    j->base.deadline_ns = deadline;
    j->mu = &mu;
    j->cv = &cv;
    j->gate = gate;
}

/* Waits (hang guard 20 s) until *field of j reaches want. */
static void wait_for(tjob *j, int *field, int want) {
    struct timespec until;
    clock_gettime(CLOCK_REALTIME, &until);
    until.tv_sec += 20;
    pthread_mutex_lock(&mu);
    while (*field < want) {
        if (pthread_cond_timedwait(&cv, &mu, &until) != 0) {
            pthread_mutex_unlock(&mu);
            fail_msg("job %p: gave up waiting", (void *)j);
        }
    }
    pthread_mutex_unlock(&mu);
}

static void open_gate(int *gate) {
    pthread_mutex_lock(&mu);
    *gate = 1;
    pthread_cond_broadcast(&cv);
    pthread_mutex_unlock(&mu);
}

static void test_runs_jobs_in_order(void **state) {
    (void)state;
    srv_pool *p = srv_pool_new(1, 8);
    assert_non_null(p);
    tjob j[5];
    int gate = 0;
    run_counter = 0;
    for (int i = 0; i < 5; i++) {
        init_job(&j[i], &gate, 0);
        assert_int_equal(srv_pool_submit(p, &j[i].base), SRV_POOL_OK);
    }
    open_gate(&gate);
    for (int i = 0; i < 5; i++) wait_for(&j[i], &j[i].released, 1);
    for (int i = 0; i < 5; i++) {
        assert_int_equal(j[i].ran, 1);
        assert_int_equal(j[i].done_calls, 1);
        assert_int_equal(j[i].outcome, SRV_JOB_RAN);
        assert_int_equal(j[i].order, i); /* FIFO with one worker */
        assert_int_equal(j[i].saw_abandoned, 0);
    }
    assert_int_equal(srv_pool_free(p, 5), 0);
}

static void test_bounded_queue_refuses_overflow(void **state) {
    (void)state;
    srv_pool *p = srv_pool_new(1, 2);
    assert_non_null(p);
    int gate = 0;
    tjob a, b, c, d;
    init_job(&a, &gate, 0);
    init_job(&b, &gate, 0);
    init_job(&c, &gate, 0);
    init_job(&d, &gate, 0);
    assert_int_equal(srv_pool_submit(p, &a.base), SRV_POOL_OK);
    wait_for(&a, &a.started, 1); /* a runs: the queue is empty again */
    assert_int_equal(srv_pool_submit(p, &b.base), SRV_POOL_OK);
    assert_int_equal(srv_pool_submit(p, &c.base), SRV_POOL_OK);
    size_t queued, running;
    srv_pool_stats(p, &queued, &running);
    assert_int_equal(queued, 2);
    assert_int_equal(running, 1);
    /* Full: refused, and none of d's callbacks will be called. */
    assert_int_equal(srv_pool_submit(p, &d.base), SRV_POOL_FULL);
    open_gate(&gate);
    wait_for(&c, &c.released, 1);
    wait_for(&b, &b.released, 1);
    wait_for(&a, &a.released, 1);
    /* Recovered: room again. */
    assert_int_equal(srv_pool_submit(p, &d.base), SRV_POOL_OK);
    wait_for(&d, &d.released, 1);
    assert_int_equal(d.outcome, SRV_JOB_RAN);
    assert_int_equal(srv_pool_free(p, 5), 0);
}

/* Jobs submitted faster than an idle worker wakes up still fit: the
 * capacity is queue_cap waiting plus one per worker. */
static void test_capacity_counts_idle_workers(void **state) {
    (void)state;
    srv_pool *p = srv_pool_new(2, 1);
    assert_non_null(p);
    int gate = 0;
    tjob j[4];
    for (int i = 0; i < 4; i++) init_job(&j[i], &gate, 0);
    assert_int_equal(srv_pool_submit(p, &j[0].base), SRV_POOL_OK);
    assert_int_equal(srv_pool_submit(p, &j[1].base), SRV_POOL_OK);
    assert_int_equal(srv_pool_submit(p, &j[2].base), SRV_POOL_OK);
    assert_int_equal(srv_pool_submit(p, &j[3].base), SRV_POOL_FULL);
    open_gate(&gate);
    for (int i = 0; i < 3; i++) wait_for(&j[i], &j[i].released, 1);
    assert_int_equal(srv_pool_free(p, 5), 0);
}

static void test_deadline_drops_queued_job(void **state) {
    (void)state;
    srv_pool *p = srv_pool_new(1, 4);
    assert_non_null(p);
    int gate = 0;
    tjob blocker, late;
    init_job(&blocker, &gate, 0);
    init_job(&late, NULL, srv_now_ns() + 20 * 1000 * 1000);
    assert_int_equal(srv_pool_submit(p, &blocker.base), SRV_POOL_OK);
    wait_for(&blocker, &blocker.started, 1);
    assert_int_equal(srv_pool_submit(p, &late.base), SRV_POOL_OK);
    /* The worker is held; the queued job's deadline passes. */
    wait_for(&late, &late.released, 1);
    assert_int_equal(late.done_calls, 1);
    assert_int_equal(late.outcome, SRV_JOB_EXPIRED);
    assert_int_equal(late.started, 0); /* dropped without running */
    size_t queued;
    srv_pool_stats(p, &queued, NULL);
    assert_int_equal(queued, 0);
    open_gate(&gate);
    wait_for(&blocker, &blocker.released, 1);
    assert_int_equal(blocker.outcome, SRV_JOB_RAN);
    assert_int_equal(srv_pool_free(p, 5), 0);
}

static void test_deadline_abandons_running_job(void **state) {
    (void)state;
    srv_pool *p = srv_pool_new(2, 4);
    assert_non_null(p);
    int gate = 0;
    tjob slow;
    init_job(&slow, &gate, srv_now_ns() + 20 * 1000 * 1000);
    assert_int_equal(srv_pool_submit(p, &slow.base), SRV_POOL_OK);
    /* done(EXPIRED) arrives while run() is still blocked... */
    wait_for(&slow, &slow.done_calls, 1);
    assert_int_equal(slow.outcome, SRV_JOB_EXPIRED);
    assert_int_equal(slow.ran, 0);
    assert_int_equal(slow.released, 0); /* the pool still holds it */
    assert_true(srv_job_abandoned(&slow.base));
    /* ...and when run() ends, only release() follows. */
    open_gate(&gate);
    wait_for(&slow, &slow.released, 1);
    assert_int_equal(slow.done_calls, 1);
    assert_int_equal(slow.saw_abandoned, 1);
    assert_int_equal(srv_pool_free(p, 5), 0);
}

static void test_cancel_all(void **state) {
    (void)state;
    srv_pool *p = srv_pool_new(1, 4);
    assert_non_null(p);
    int gate = 0;
    tjob running, queued1, queued2;
    init_job(&running, &gate, 0);
    init_job(&queued1, &gate, 0);
    init_job(&queued2, &gate, 0);
    assert_int_equal(srv_pool_submit(p, &running.base), SRV_POOL_OK);
    wait_for(&running, &running.started, 1);
    assert_int_equal(srv_pool_submit(p, &queued1.base), SRV_POOL_OK);
    assert_int_equal(srv_pool_submit(p, &queued2.base), SRV_POOL_OK);
    srv_pool_cancel_all(p);
    assert_int_equal(queued1.done_calls, 1);
    assert_int_equal(queued1.outcome, SRV_JOB_CANCELLED);
    assert_int_equal(queued1.released, 1);
    assert_int_equal(queued2.outcome, SRV_JOB_CANCELLED);
    assert_int_equal(running.done_calls, 1);
    assert_int_equal(running.outcome, SRV_JOB_CANCELLED);
    assert_int_equal(running.released, 0);
    /* A second cancel finds nothing new. */
    srv_pool_cancel_all(p);
    assert_int_equal(running.done_calls, 1);
    open_gate(&gate);
    wait_for(&running, &running.released, 1);
    assert_int_equal(queued1.started, 0);
    assert_int_equal(srv_pool_free(p, 5), 0);
}

static void test_shutdown_waits_then_refuses(void **state) {
    (void)state;
    srv_pool *p = srv_pool_new(2, 4);
    assert_non_null(p);
    int gate = 1;
    tjob j[4];
    for (int i = 0; i < 4; i++) {
        init_job(&j[i], &gate, 0);
        assert_int_equal(srv_pool_submit(p, &j[i].base), SRV_POOL_OK);
    }
    /* Free waits for queued and running jobs to finish, then joins. */
    assert_int_equal(srv_pool_free(p, 20), 0);
    for (int i = 0; i < 4; i++) {
        assert_int_equal(j[i].outcome, SRV_JOB_RAN);
        assert_int_equal(j[i].released, 1);
    }
    assert_int_equal(srv_pool_free(NULL, 0), 0);
}

static void test_shutdown_does_not_wait_forever(void **state) {
    (void)state;
    srv_pool *p = srv_pool_new(1, 1);
    assert_non_null(p);
    static int gate = 0;
    static tjob stuck;
    init_job(&stuck, &gate, 0);
    assert_int_equal(srv_pool_submit(p, &stuck.base), SRV_POOL_OK);
    wait_for(&stuck, &stuck.started, 1);
    /* A job that does not look at srv_job_abandoned cannot be stopped
     * (the compute jobs do; this one waits on its gate): free gives up
     * (-1), leaving the pool alive; submissions are refused from then
     * on. */
    assert_int_equal(srv_pool_free(p, 0.05), -1);
    tjob other;
    init_job(&other, NULL, 0);
    assert_int_equal(srv_pool_submit(p, &other.base), SRV_POOL_CLOSED);
    /* Let it finish and free for real. */
    open_gate(&gate);
    wait_for(&stuck, &stuck.released, 1);
    assert_int_equal(srv_pool_free(p, 5), 0);
}

static void test_close_refuses_but_finishes(void **state) {
    (void)state;
    srv_pool *p = srv_pool_new(1, 2);
    assert_non_null(p);
    int gate = 0;
    tjob a, b, c;
    init_job(&a, &gate, 0);
    init_job(&b, &gate, 0);
    init_job(&c, NULL, 0);
    assert_int_equal(srv_pool_submit(p, &a.base), SRV_POOL_OK);
    assert_int_equal(srv_pool_submit(p, &b.base), SRV_POOL_OK);
    srv_pool_close(p);
    assert_int_equal(srv_pool_submit(p, &c.base), SRV_POOL_CLOSED);
    open_gate(&gate);
    wait_for(&a, &a.released, 1);
    wait_for(&b, &b.released, 1);
    assert_int_equal(a.outcome, SRV_JOB_RAN);
    assert_int_equal(b.outcome, SRV_JOB_RAN);
    assert_int_equal(c.done_calls, 0);
    assert_int_equal(srv_pool_free(p, 5), 0);
}

static void test_clamps_sizes(void **state) {
    (void)state;
    srv_pool *p = srv_pool_new(0, 0); /* clamped to 1 and 1 */
    assert_non_null(p);
    tjob a;
    init_job(&a, NULL, 0);
    assert_int_equal(srv_pool_submit(p, &a.base), SRV_POOL_OK);
    wait_for(&a, &a.released, 1);
    assert_int_equal(srv_pool_free(p, 5), 0);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_runs_jobs_in_order),
        cmocka_unit_test(test_bounded_queue_refuses_overflow),
        cmocka_unit_test(test_capacity_counts_idle_workers),
        cmocka_unit_test(test_deadline_drops_queued_job),
        cmocka_unit_test(test_deadline_abandons_running_job),
        cmocka_unit_test(test_cancel_all),
        cmocka_unit_test(test_shutdown_waits_then_refuses),
        cmocka_unit_test(test_shutdown_does_not_wait_forever),
        cmocka_unit_test(test_close_refuses_but_finishes),
        cmocka_unit_test(test_clamps_sizes),
    };
    return cmocka_run_group_tests_name("server/pool", tests, NULL, NULL);
}
