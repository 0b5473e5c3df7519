/* budget.c -- the memory budget of requests in flight (budget.h). */
#include "budget.h"

#include <stdatomic.h>
#include <stdlib.h>

struct srv_budget {
    size_t capacity, large_limit;
    atomic_size_t used, peak, refused;
};

srv_budget *srv_budget_new(size_t capacity) {
    srv_budget *b = calloc(1, sizeof *b);
    if (b == NULL) return NULL;
    b->capacity = capacity;
    b->large_limit = capacity - capacity / 16;
    atomic_init(&b->used, 0);
    atomic_init(&b->peak, 0);
    atomic_init(&b->refused, 0);
    return b;
}

void srv_budget_free(srv_budget *b) { free(b); }

int srv_budget_take(srv_budget *b, size_t n) {
    size_t limit = n > SRV_BUDGET_SMALL ? b->large_limit : b->capacity;
    size_t used = atomic_load(&b->used);
    do {
        if (n > limit || used > limit - n) {
            atomic_fetch_add(&b->refused, 1);
            return -1;
        }
    } while (!atomic_compare_exchange_weak(&b->used, &used, used + n));
    size_t now = used + n, peak = atomic_load(&b->peak);
    while (now > peak && !atomic_compare_exchange_weak(&b->peak, &peak, now)) {
    }
    return 0;
}

void srv_budget_force(srv_budget *b, size_t n) {
    size_t now = atomic_fetch_add(&b->used, n) + n, peak = atomic_load(&b->peak);
    while (now > peak && !atomic_compare_exchange_weak(&b->peak, &peak, now)) {
    }
}

void srv_budget_give(srv_budget *b, size_t n) {
    atomic_fetch_sub(&b->used, n);
}

size_t srv_budget_capacity(const srv_budget *b) { return b->capacity; }

size_t srv_budget_used(const srv_budget *b) {
    return atomic_load(&((srv_budget *)b)->used);
}

size_t srv_budget_peak(const srv_budget *b) {
    return atomic_load(&((srv_budget *)b)->peak);
}

size_t srv_budget_refused(const srv_budget *b) {
    return atomic_load(&((srv_budget *)b)->refused);
}
