/* budget.h -- one memory budget for everything the service holds for
 * requests in flight: the bodies being received, the computations being
 * run (estimated from their size before they start), and the answers
 * waiting to be sent.
 *
 * A counter of bytes against a capacity (--answer-memory), changed with
 * atomic compare-and-swap: srv_budget_take succeeds only if the bytes fit,
 * so the total never passes the capacity. Large takes may use the
 * capacity less a sixteenth, which is kept for small ones: when large
 * work has spent the budget, small requests are still served. Cost: one
 * atomic operation per take or give. */
#ifndef VOR_SRV_BUDGET_H
#define VOR_SRV_BUDGET_H

#include <stddef.h>

typedef struct srv_budget srv_budget;

/* A take of more than this is large. */
#define SRV_BUDGET_SMALL ((size_t)1 << 20)

srv_budget *srv_budget_new(size_t capacity);
void srv_budget_free(srv_budget *b);

/* Takes n bytes if they fit (see above): 0, else -1 and nothing taken. */
int srv_budget_take(srv_budget *b, size_t n);

/* Takes n bytes whether they fit or not (an estimate that fell short:
 * the bytes are held anyway). */
void srv_budget_force(srv_budget *b, size_t n);

/* Gives back n bytes taken before. */
void srv_budget_give(srv_budget *b, size_t n);

size_t srv_budget_capacity(const srv_budget *b);
size_t srv_budget_used(const srv_budget *b);
/* The most ever held at once. */
size_t srv_budget_peak(const srv_budget *b);
/* Takes refused so far. */
size_t srv_budget_refused(const srv_budget *b);

#endif /* VOR_SRV_BUDGET_H */
