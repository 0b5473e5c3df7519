/* allocator.h -- the daemon's settings of glibc's allocator, in one place
 * for voronoid (main.c) and for the bench, which measures time and peak
 * memory as the daemon has them.
 *
 * Called once, before any thread starts: keep up to 16 MiB of free memory
 * per arena rather than give it back to the system after every request,
 * and map blocks of their own only from 4 MiB up. By default glibc trims a
 * thread's heap once 128 KiB lie free at its top and maps every block from
 * 128 KiB until its adaptive threshold has seen big ones, so each small
 * request paid for madvise() and the page faults of memory it had just
 * returned (about a tenth of its time); large requests still return their
 * memory. (The adaptive threshold also makes a large computation's peak
 * depend on the order of its frees: blocks freed after it has risen stay
 * in the heap beside new ones. Fortune at 10^6 uniform sites peaks at 180
 * bytes per site with it, 168 with the fixed one.) Fast bins are turned
 * off: a small request frees more small blocks than the thread cache
 * keeps (the libmicrohttpd response headers, allocated with calloc, which
 * bypasses that cache), so they piled up in fast bins that the answer's
 * first block of over 1 KiB then had to consolidate: about 950
 * instructions of a 10-point request's 122,000, against 400 more in free()
 * without them. */
#ifndef SRV_ALLOCATOR_H
#define SRV_ALLOCATOR_H

#include <malloc.h>

static inline void srv_tune_allocator(void) {
#if defined(M_TRIM_THRESHOLD) && defined(M_MMAP_THRESHOLD)
    mallopt(M_MMAP_THRESHOLD, 4 << 20);
    mallopt(M_TRIM_THRESHOLD, 16 << 20);
#endif
#if defined(M_MXFAST)
    mallopt(M_MXFAST, 0);
#endif
}

#endif
