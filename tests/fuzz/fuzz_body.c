/* fuzz_body.c -- libFuzzer target: request bodies never crash, hang or leak.
 *
 * The first byte picks the body kind (JSON, text, binary) and the output
 * format; the rest is the body. Whatever it is, parsing ends in API_OK or in
 * a problem with a status and a detail; a successful parse of a small point
 * set is computed and written, and a failed one's problem is written. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../api/api.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    if (size == 0) return 0;
    api_input kind = (api_input)(data[0] % 3);
    api_format fmt = (api_format)((data[0] / 3) % 4);
    api_limits lim = {.max_points = 512};
    api_request r;
    api_problem p;
    api_buf out;
    api_request_init(&r);
    api_buf_init(&out);
    memset(&p, 0, sizeof p);

    api_code c = api_parse_body(&r, kind, (const char *)data + 1, size - 1,
                                &lim, &p);
    if (c == API_OK && r.n <= 512) {
        r.format = fmt;
        api_result res;
        api_result_init(&res);
        c = api_compute(&r, &res, &p);
        if (c == API_OK) c = api_write_result(&r, &res, &res.t, &out, &p);
        api_result_clear(&res);
    }
    if (c != API_OK) {
        if (p.code == API_OK || p.detail[0] == '\0') {
            fprintf(stderr, "fuzz_body: problem without code or detail\n");
            abort();
        }
        api_buf_clear(&out);
        api_buf_init(&out);
        api_write_problem(&p, "/voronoi", &out);
        if (out.len == 0 || out.data[0] != '{') {
            fprintf(stderr, "fuzz_body: empty problem body\n");
            abort();
        }
    }
    api_buf_clear(&out);
    api_request_clear(&r);
    return 0;
}
