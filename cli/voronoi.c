/* voronoi.c -- the command line front end of the codec (being written):
 * for now it only says so. */
#include <stdio.h>

int main(void) {
    fputs("voronoi: not built yet\n", stderr);
    return 1;
}
