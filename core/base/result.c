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

spr_result spr__fail(spr_error *err, spr_result code, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        err->code = code;
        vsnprintf(err->msg, sizeof err->msg, fmt, ap);
        va_end(ap);
    }
    return code;
}
