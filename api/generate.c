/* generate.c -- generated point sets for requests that ask for them
 * ("generate": {"distribution", "n", "seed"}) and for the command line.
 *
 * The generator is xoshiro256** seeded through splitmix64: fast, good
 * statistical quality, and the same sequence on every platform for a seed
 * (rand() is neither). Only gaussian, circle and clustered call libm (log,
 * sqrt, sin, cos), whose last bits may differ between C libraries. Cost:
 * O(n) time, one array of 2n doubles. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"

typedef struct rng {
    uint64_t s[4];
} rng;

static uint64_t splitmix64(uint64_t *x) {
    uint64_t z = (*x += 0x9e3779b97f4a7c15u);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
    return z ^ (z >> 31);
}

static void rng_seed(rng *r, uint64_t seed) {
    for (int i = 0; i < 4; i++) r->s[i] = splitmix64(&seed);
}

static inline uint64_t rotl(uint64_t x, int k) {
    return (x << k) | (x >> (64 - k));
}

static uint64_t rng_next(rng *r) {
    uint64_t *s = r->s;
    uint64_t result = rotl(s[1] * 5, 7) * 9;
    uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = rotl(s[3], 45);
    return result;
}

/* Uniform in [0, 1), 53 random bits. */
static double rng_unit(rng *r) { return (double)(rng_next(r) >> 11) * 0x1p-53; }

/* Uniform integer in [0, m), without modulo bias (m > 0). */
static uint64_t rng_below(rng *r, uint64_t m) {
    uint64_t limit = UINT64_MAX - UINT64_MAX % m;
    uint64_t v;
    do {
        v = rng_next(r);
    } while (v >= limit);
    return v % m;
}

/* Two independent standard normal values (Box-Muller). */
static void rng_gauss2(rng *r, double *a, double *b) {
    double u1 = (double)((rng_next(r) >> 11) + 1) * 0x1p-53; /* (0, 1] */
    double u2 = rng_unit(r);
    double rad = sqrt(-2.0 * log(u1));
    double t = 6.283185307179586 * u2;
    *a = rad * cos(t);
    *b = rad * sin(t);
}

static void gen_uniform(rng *r, double *xy, size_t n) {
    for (size_t i = 0; i < 2 * n; i++) xy[i] = rng_unit(r);
}

static void gen_gaussian(rng *r, double *xy, size_t n) {
    for (size_t i = 0; i < n; i++) rng_gauss2(r, &xy[2 * i], &xy[2 * i + 1]);
}

static void gen_random(rng *r, double *xy, size_t n) {
    for (size_t i = 0; i < n; i++) {
        xy[2 * i] = (double)rng_below(r, 800);
        xy[2 * i + 1] = (double)rng_below(r, 600);
    }
}

static void gen_grid(rng *r, double *xy, size_t n) {
    (void)r;
    size_t k = (size_t)sqrt((double)n);
    while (k * k < n) k++;
    while (k > 0 && (k - 1) * (k - 1) >= n) k--;
    for (size_t i = 0; i < n; i++) {
        xy[2 * i] = (double)(i % k);
        xy[2 * i + 1] = (double)(i / k);
    }
}

static void gen_circle(rng *r, double *xy, size_t n) {
    (void)r;
    for (size_t i = 0; i < n; i++) {
        double t = 6.283185307179586 * (double)i / (double)n;
        xy[2 * i] = cos(t);
        xy[2 * i + 1] = sin(t);
    }
}

static void gen_clustered(rng *r, double *xy, size_t n) {
    size_t c = (size_t)floor(sqrt((double)n) / 10 + 0.5);
    if (c < 1) c = 1;
    if (c > 1000) c = 1000;
    double centres[2 * 1000];
    for (size_t j = 0; j < 2 * c; j++) centres[j] = rng_unit(r);
    double sd = 0.1 / sqrt((double)c);
    for (size_t i = 0; i < n; i++) {
        size_t j = (size_t)rng_below(r, c);
        double a, b;
        rng_gauss2(r, &a, &b);
        xy[2 * i] = centres[2 * j] + sd * a;
        xy[2 * i + 1] = centres[2 * j + 1] + sd * b;
    }
}

static const struct {
    const char *name;
    void (*fill)(rng *r, double *xy, size_t n);
} generators[] = {
    {"uniform", gen_uniform}, {"gaussian", gen_gaussian},
    {"random", gen_random},   {"grid", gen_grid},
    {"circle", gen_circle},   {"clustered", gen_clustered},
};

api_code api_generate(const char *distribution, size_t n, uint64_t seed,
                      double **xy, api_problem *p) {
    *xy = NULL;
    size_t g = 0, count = sizeof generators / sizeof generators[0];
    while (g < count &&
           (distribution == NULL || strcmp(distribution, generators[g].name))) {
        g++;
    }
    if (g == count) {
        char shown[80];
        const char *d = distribution ? distribution : "";
        api__quote_excerpt(shown, sizeof shown, d, strlen(d), 40);
        return api__problem_at(p, API_INVALID, NULL, 0,
                               "unknown distribution \"%s\"; valid: uniform, "
                               "gaussian, random, grid, circle, clustered",
                               shown);
    }
    if (n > VOR_MAX_POINTS) {
        return api__problem_at(p, API_TOO_LARGE, NULL, 0,
                               "cannot generate %zu points: the limit is %zu", n,
                               (size_t)VOR_MAX_POINTS);
    }
    if (n == 0) return API_OK;
    double *out = malloc(n * 2 * sizeof(double));
    if (out == NULL) {
        return api__problem_at(p, API_UNAVAILABLE, NULL, 0,
                               "out of memory generating %zu points", n);
    }
    rng r;
    rng_seed(&r, seed);
    generators[g].fill(&r, out, n);
    *xy = out;
    return API_OK;
}
