/* result.c — messages of spr_result and the error-filling helper. */
#include "spr_result.h"

#include <stdarg.h>
#include <stdio.h>

const char *spr_strerror(spr_result r)
{
    switch (r) {
#define SPR__X(name, value, msg) case name: return msg;
        SPR_RESULT_LIST(SPR__X)
#undef SPR__X
    }
    return "unknown error";
}

void spr__one_line(char *dst, size_t cap, const char *src)
{
    size_t o = 0;
    for (const unsigned char *p = (const unsigned char *)src; *p && o + 5 < cap; p++) {
        if (*p >= 0x20 && *p != 0x7f) dst[o++] = (char)*p;
        else if (*p == '\n') dst[o++] = '\\', dst[o++] = 'n';
        else o += (size_t)snprintf(dst + o, cap - o, "\\x%02x", *p);
    }
    if (cap) dst[o] = '\0';
}

spr_result spr__fail(spr_error *err, spr_result code, const char *fmt, ...)
{
    if (err) {
        char raw[sizeof err->msg];
        va_list ap;
        va_start(ap, fmt);
        err->code = code;
        vsnprintf(raw, sizeof raw, fmt, ap);
        va_end(ap);
        /* one line whatever a file holds (a name or key it quotes may hold control characters) */
        spr__one_line(err->msg, sizeof err->msg, raw);
    }
    return code;
}
