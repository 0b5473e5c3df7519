/* test_stop.c -- vor_options.stop: a run told to stop gives up.
 *
 *   - asked and never told to stop, every algorithm returns the diagram
 *     it returns without the question, bit for bit, and asks at least once
 *     per VOR_STOP_EVERY sites (so a stop is heard within that many);
 *   - told to stop at its first question, or at a later one, in the middle
 *     of its work, every algorithm returns VOR_ESTOPPED with no diagram,
 *     asks nothing more, and leaks nothing (the sanitizer build checks);
 *     its counts describe the work done until then, less than a whole run;
 *   - the same with a trace: the steps end where the run stopped, without
 *     the END step;
 *   - input no algorithm sees (fewer than three sites, one line) is
 *     answered without a question. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "../../core/vor.h"
#include "../support/testsets.h"

typedef struct asker {
    long asked;   /* questions so far */
    long stop_at; /* answer "stop" from this question on (0: never) */
} asker;

static int ask(void *ctx) {
    asker *a = ctx;
    a->asked++;
    return a->stop_at != 0 && a->asked >= a->stop_at;
}

typedef struct steps {
    long n, ends;
} steps;

static void on_step(void *ctx, const vor_step *st) {
    steps *s = ctx;
    s->n++;
    s->ends += st->kind == VOR_STEP_END;
}

static vor_sites *sites_of(const double *xy, size_t n) {
    vor_sites *s = NULL;
    assert_int_equal(vor_sites_new(xy, n, &s, NULL), VOR_OK);
    return s;
}

/* The sets: random, a grid (cocircular everywhere: the slow paths) and a
 * circle (Fortune's events all at the end). */
enum { N_SETS = 3 };
static vor_sites *make_set(int k) {
    double *xy;
    size_t n;
    if (k == 0) {
        n = 30000;
        xy = vt_uniform(n, 7);
    } else if (k == 1) {
        n = 150 * 150;
        xy = vt_grid(150, 150);
    } else {
        n = 20000;
        xy = vt_unit_circle(n);
    }
    vor_sites *s = sites_of(xy, n);
    free(xy);
    return s;
}

static void test_never_told(void **state) {
    (void)state;
    for (int k = 0; k < N_SETS; k++) {
        vor_sites *s = make_set(k);
        for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
            vor_diagram *plain = NULL, *asked = NULL;
            assert_int_equal(vor_compute(s, (vor_algorithm)a, &plain), VOR_OK);
            asker q = {0, 0};
            vor_options o = {.stop = ask, .stop_ctx = &q};
            assert_int_equal(vor_compute_ex(s, (vor_algorithm)a, &o, &asked),
                             VOR_OK);
            assert_true(vor_diagram_equal(plain, asked));
            /* the first question comes before any work, then one per
             * VOR_STOP_EVERY sites at least */
            assert_true(q.asked >= 1 + (long)((s->n - 3) / VOR_STOP_EVERY));
            vor_diagram_free(plain);
            vor_diagram_free(asked);
        }
        vor_sites_free(s);
    }
}

static void test_told_to_stop(void **state) {
    (void)state;
    const long at[] = {1, 2, 7};
    for (int k = 0; k < N_SETS; k++) {
        vor_sites *s = make_set(k);
        for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
            vor_counts whole;
            vor_options ow = {.counts = &whole};
            vor_diagram *d = NULL;
            assert_int_equal(vor_compute_ex(s, (vor_algorithm)a, &ow, &d),
                             VOR_OK);
            vor_diagram_free(d);
            for (size_t i = 0; i < sizeof at / sizeof at[0]; i++) {
                asker q = {0, at[i]};
                vor_counts c;
                vor_options o = {.counts = &c, .stop = ask,
                                 .stop_ctx = &q};
                d = (vor_diagram *)&q; /* must be cleared */
                assert_int_equal(vor_compute_ex(s, (vor_algorithm)a, &o, &d),
                                 VOR_ESTOPPED);
                assert_null(d);
                assert_int_equal(q.asked, at[i]); /* no question after */
                /* less work than a whole run: fewer sites inserted or
                 * swept */
                if (a == VOR_FORTUNE)
                    assert_true(c.site_events < whole.site_events);
                else
                    assert_true(c.orient2d < whole.orient2d);
            }
        }
        vor_sites_free(s);
    }
}

static void test_stop_while_tracing(void **state) {
    (void)state;
    double *xy = vt_uniform(3000, 11);
    vor_sites *s = sites_of(xy, 3000);
    free(xy);
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
        steps whole = {0, 0}, cut = {0, 0};
        vor_options ow = {.trace = on_step, .trace_ctx = &whole};
        vor_diagram *d = NULL;
        assert_int_equal(vor_compute_ex(s, (vor_algorithm)a, &ow, &d), VOR_OK);
        vor_diagram_free(d);
        assert_int_equal(whole.ends, 1);
        asker q = {0, 2};
        vor_options o = {.trace = on_step, .trace_ctx = &cut, .stop = ask,
                         .stop_ctx = &q};
        assert_int_equal(vor_compute_ex(s, (vor_algorithm)a, &o, &d),
                         VOR_ESTOPPED);
        assert_null(d);
        assert_int_equal(cut.ends, 0);
        assert_true(cut.n > 0 && cut.n < whole.n);
    }
    vor_sites_free(s);
}

static void test_no_question_without_work(void **state) {
    (void)state;
    const double two[] = {0, 0, 1, 1};
    const double line[] = {0, 0, 1, 1, 2, 2, 3, 3};
    vor_sites *sets[] = {sites_of(two, 2), sites_of(line, 4)};
    for (int k = 0; k < 2; k++) {
        for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
            asker q = {0, 1};
            vor_options o = {.stop = ask, .stop_ctx = &q};
            vor_diagram *d = NULL;
            assert_int_equal(vor_compute_ex(sets[k], (vor_algorithm)a, &o, &d),
                             VOR_OK);
            assert_int_equal(q.asked, 0);
            vor_diagram_free(d);
        }
        vor_sites_free(sets[k]);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_never_told),
        cmocka_unit_test(test_told_to_stop),
        cmocka_unit_test(test_stop_while_tracing),
        cmocka_unit_test(test_no_question_without_work),
    };
    return cmocka_run_group_tests_name("core/stop", tests, NULL, NULL);
}
