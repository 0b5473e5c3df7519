/* fault_alloc.h -- allocation failure injection for a test binary.
 *
 * Include in exactly one test file: it defines malloc, calloc and realloc
 * for the whole program, forwarding to the next definition (the C library
 * or the AddressSanitizer runtime, found with dlsym(RTLD_NEXT)), so leak
 * detection keeps working. While armed, the allocation numbered
 * fault_countdown (0 = the next one) fails and every later one succeeds;
 * fault_seen counts the allocations made while armed. The usual loop:
 *
 *     n = count allocations of f() (fault_arm(-1), f(), fault_disarm());
 *     for k in 0..n-1: fault_arm(k); f() must fail cleanly; fault_disarm();
 *
 * and LeakSanitizer at exit reports anything an error path forgot.
 * Single-threaded tests only.
 */
#ifndef VOR_TESTS_FAULT_ALLOC_H
#define VOR_TESTS_FAULT_ALLOC_H

#include <dlfcn.h>
#include <stddef.h>
#include <string.h>

static int fault_armed;
static long fault_countdown = -1;
static long fault_also = -1;
static long fault_seen;

static void fault_arm(long countdown) {
    fault_seen = 0;
    fault_countdown = countdown;
    fault_also = -1;
    fault_armed = 1;
}

/* As fault_arm(countdown), and the allocation numbered also fails too:
 * for the allocations of a path that only the first failure opens. */
static inline void fault_arm_two(long countdown, long also) {
    fault_arm(countdown);
    fault_also = also;
}

static void fault_disarm(void) { fault_armed = 0; }

/* Decides for one allocation: 1 = fail it. */
static int fault_now(void) {
    if (!fault_armed) return 0;
    int also = fault_seen == fault_also;
    fault_seen++;
    return (fault_countdown-- == 0) | also;
}

typedef void *(*fault_malloc_fn)(size_t);
typedef void *(*fault_calloc_fn)(size_t, size_t);
typedef void *(*fault_realloc_fn)(void *, size_t);

/* dlsym itself may allocate (calloc) before the real functions are known:
 * those few early requests are served from a static arena and never
 * freed (free() of them is never reached: they belong to the dynamic
 * linker). */
static unsigned char fault_arena[4096];
static size_t fault_arena_used;

static void *fault_arena_alloc(size_t n) {
    n = (n + 15) & ~(size_t)15;
    if (fault_arena_used + n > sizeof fault_arena) return NULL;
    void *p = fault_arena + fault_arena_used;
    fault_arena_used += n;
    return p;
}

static int fault_resolving;

void *malloc(size_t n);
void *calloc(size_t a, size_t b);
void *realloc(void *p, size_t n);

void *malloc(size_t n) {
    static fault_malloc_fn real;
    if (!real) {
        if (fault_resolving) return fault_arena_alloc(n);
        fault_resolving = 1;
        *(void **)&real = dlsym(RTLD_NEXT, "malloc");
        fault_resolving = 0;
    }
    if (fault_now()) return NULL;
    return real(n);
}

void *calloc(size_t a, size_t b) {
    static fault_calloc_fn real;
    if (!real) {
        if (fault_resolving) {
            void *p = fault_arena_alloc(a * b);
            if (p) memset(p, 0, a * b);
            return p;
        }
        fault_resolving = 1;
        *(void **)&real = dlsym(RTLD_NEXT, "calloc");
        fault_resolving = 0;
    }
    if (fault_now()) return NULL;
    return real(a, b);
}

void *realloc(void *p, size_t n) {
    static fault_realloc_fn real;
    if (!real) {
        fault_resolving = 1;
        *(void **)&real = dlsym(RTLD_NEXT, "realloc");
        fault_resolving = 0;
    }
    if (fault_now()) return NULL;
    return real(p, n);
}

#endif /* VOR_TESTS_FAULT_ALLOC_H */
