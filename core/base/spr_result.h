/* spr_result.h — error values of the splatref library.
 *
 * Every fallible function returns an spr_result (0 = success, negative =
 * failure) and, where it can say more, fills an spr_error with one line of
 * text naming the file and the position.  The codes and their default
 * messages come from one X-macro table so tests can assert exact codes.
 */
#ifndef SPR_RESULT_H
#define SPR_RESULT_H

#include <stddef.h>

#define SPR_RESULT_LIST(X)                                              \
    X(SPR_OK,            0, "success")                                  \
    X(SPR_E_IO,         -1, "input/output error")                       \
    X(SPR_E_FORMAT,     -2, "malformed input")                          \
    X(SPR_E_TRUNCATED,  -3, "truncated input")                          \
    X(SPR_E_VALUE,      -4, "invalid value (NaN, Inf, zero or negative)") \
    X(SPR_E_TOO_LARGE,  -5, "size beyond the supported limits")         \
    X(SPR_E_NOMEM,      -6, "out of memory")                            \
    X(SPR_E_ARG,        -7, "invalid argument")                         \
    X(SPR_E_BACKEND,    -8, "backend failure")                          \
    X(SPR_E_NO_DEVICE,  -9, "no device: no EGL display or GL context can be created")

typedef enum spr_result {
#define SPR__X(name, value, msg) name = value,
    SPR_RESULT_LIST(SPR__X)
#undef SPR__X
} spr_result;

/* One-line description of an error: the code and the text to print. */
typedef struct spr_error {
    spr_result code;
    char msg[512];
} spr_error;

/* Static message of a code (never NULL). */
const char *spr_strerror(spr_result r);

/* src into dst (cap bytes) as one line: control characters as C escapes (\n, \xNN); cut to fit. */
void spr__one_line(char *dst, size_t cap, const char *src);

/* Fill err (may be NULL) with code and a printf-formatted line (made one line by spr__one_line); returns code. */
spr_result spr__fail(spr_error *err, spr_result code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* Largest cloud, image side and group count the library accepts: beyond
 * these, inputs are rejected as absurd before any allocation. */
#define SPR_MAX_SPLATS   (1u << 28)   /* 268M splats */
#define SPR_MAX_IMAGE_SIDE 16384
#define SPR_MAX_GROUPS   256

#endif
