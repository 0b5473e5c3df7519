/* check.c -- vor_check, the diagram checker (placeholder: reports every
 * diagram as unchecked). */
#include <stdio.h>

#include "internal.h"

int vor_check(const vor_diagram *d, const vor_sites *sites, char *msg,
              size_t msg_size) {
    (void)d; (void)sites;
    if (msg && msg_size) snprintf(msg, msg_size, "vor_check: not implemented");
    return 1;
}
