/* distribution.c -- the named point distributions (see distribution.h for
 * what each one is).
 *
 * Each generator draws from one xoshiro256** stream seeded by splitmix64,
 * in a fixed order, so a (distribution, n, seed) names one array of doubles.
 * Changing the order of the draws changes every generated set: the tests in
 * tests/api/test_generate.c pin a few values. */
#include "distribution.h"

#include <assert.h>
#include <math.h>
#include <string.h>

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

/* The top 53 bits of a draw as a double in [0, 1). */
static double unit_of(uint64_t v) { return (double)(v >> 11) * 0x1p-53; }

static double rng_unit(rng *r) { return unit_of(rng_next(r)); }

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

static void gen_pixels(rng *r, double *xy, size_t n) {
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

/* exp(2a), exp(2b) for a normal pair: from about exp(-17) to exp(17), the
 * extremes of Box-Muller with 53-bit uniforms. */
static void gen_lognormal(rng *r, double *xy, size_t n) {
    for (size_t i = 0; i < n; i++) {
        double a, b;
        rng_gauss2(r, &a, &b);
        xy[2 * i] = exp(2.0 * a);
        xy[2 * i + 1] = exp(2.0 * b);
    }
}

/* The stray point's position first, then the square's points in order. */
static void gen_outlier(rng *r, double *xy, size_t n) {
    if (n == 0) return;
    size_t stray = (size_t)rng_below(r, n);
    for (size_t i = 0; i < n; i++) {
        if (i == stray) {
            xy[2 * i] = 0.0;
            xy[2 * i + 1] = 0.0;
            continue;
        }
        xy[2 * i] = 8.45 + 0.1 * rng_unit(r);
        xy[2 * i + 1] = 47.25 + 0.1 * rng_unit(r);
    }
}

/* One draw per coordinate: its top 53 bits give the exponent, uniform in
 * [-6, 6), its lowest bit the sign. */
static void gen_decades(rng *r, double *xy, size_t n) {
    for (size_t i = 0; i < 2 * n; i++) {
        uint64_t v = rng_next(r);
        double m = pow(10.0, 12.0 * unit_of(v) - 6.0);
        xy[i] = v & 1 ? -m : m;
    }
}

static const struct {
    const char *name;
    int seeded;
    const char *text;
} info[] = {
#define API__DIST_INFO(id, name, seeded, text) {name, seeded, text},
    API_DIST_TABLE(API__DIST_INFO)
#undef API__DIST_INFO
};

/* Indexed by api_dist, in the order of API_DIST_TABLE. */
static void (*const fill[])(rng *r, double *xy, size_t n) = {
    gen_uniform,   gen_gaussian,  gen_pixels, gen_grid,    gen_circle,
    gen_clustered, gen_lognormal, gen_outlier, gen_decades,
};

static const struct {
    const char *alias;
    api_dist dist;
} aliases[] = {{"random", API_DIST_PIXELS}};

int api_dist_find(const char *name) {
    if (name == NULL) return -1;
    for (int d = 0; d < API_DIST_COUNT; d++) {
        if (strcmp(name, info[d].name) == 0) return d;
    }
    for (size_t a = 0; a < sizeof aliases / sizeof aliases[0]; a++) {
        if (strcmp(name, aliases[a].alias) == 0) return (int)aliases[a].dist;
    }
    return -1;
}

const char *api_dist_name(api_dist d) {
    return (unsigned)d < API_DIST_COUNT ? info[d].name : NULL;
}

const char *api_dist_text(api_dist d) {
    return (unsigned)d < API_DIST_COUNT ? info[d].text : NULL;
}

int api_dist_seeded(api_dist d) {
    return (unsigned)d < API_DIST_COUNT ? info[d].seeded : 0;
}

const char *api_dist_list(void) {
    return "uniform, gaussian, pixels (alias random), grid, circle, "
           "clustered, lognormal, outlier, decades";
}

void api_dist_fill(api_dist d, uint64_t seed, double *xy, size_t n) {
    _Static_assert(sizeof fill / sizeof fill[0] == API_DIST_COUNT,
                   "one generator per distribution");
    assert((unsigned)d < API_DIST_COUNT);
    rng r;
    rng_seed(&r, seed);
    fill[d](&r, xy, n);
}
