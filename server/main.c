/* main.c -- the voronoid daemon's entry point (placeholder while the
 * server is written: it reports that it is not available yet). */
#include <stdio.h>

int main(void) {
    fputs("voronoid: not built yet\n", stderr);
    return 1;
}
