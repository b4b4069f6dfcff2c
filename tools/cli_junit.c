/* cli_junit.c — JUnit XML reports (--junit F.xml) of check, parity,
 * parity --random and reference: one <testcase> per plane, scene or image,
 * its <failure> text the lines the terminal showed for it.  Written with
 * libxml2's xmlTextWriter (escaping, encoding, well-formedness) into memory,
 * then through spr__write_atomic (a temporary file renamed over F).  The layout is the one CI servers read
 * (Jenkins' JUnit and xUnit schema; tests/data/junit/ has the schema the
 * tests validate against). */
#include "cli.h"

#include <libxml/xmlwriter.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

typedef struct jcase {
    char *classname, *name, *message, *text;
    double seconds;
    int status;
} jcase;

struct cli_junit {
    char suite[128];
    jcase *c;
    int n, cap;
    double t0;
    char stamp[32];
};

cli_junit *cli_junit_new(const char *suite)
{
    cli_junit *j = calloc(1, sizeof *j);
    if (!j) return NULL;
    snprintf(j->suite, sizeof j->suite, "%s", suite);
    j->t0 = spr_now_ms();
    time_t now = time(NULL);
    struct tm tm;
    gmtime_r(&now, &tm);
    strftime(j->stamp, sizeof j->stamp, "%Y-%m-%dT%H:%M:%S", &tm);
    return j;
}

static char *dup_or_empty(const char *s) { return strdup(s ? s : ""); }

void cli_junit_add(cli_junit *j, const char *classname, const char *name, double seconds, int status, const char *message, const char *text)
{
    if (!j) return;
    if (j->n == j->cap) {
        int cap = j->cap ? 2 * j->cap : 16;
        jcase *c = realloc(j->c, (size_t)cap * sizeof *c);
        if (!c) return;
        j->c = c, j->cap = cap;
    }
    jcase *c = &j->c[j->n++];
    c->classname = dup_or_empty(classname), c->name = dup_or_empty(name);
    c->message = dup_or_empty(message), c->text = dup_or_empty(text);
    c->seconds = seconds, c->status = status;
}

void cli_junit_free(cli_junit *j)
{
    if (!j) return;
    for (int i = 0; i < j->n; i++) free(j->c[i].classname), free(j->c[i].name), free(j->c[i].message), free(j->c[i].text);
    free(j->c);
    free(j);
}

static int attr_num(xmlTextWriterPtr w, const char *k, double v, int is_int)
{
    return is_int ? xmlTextWriterWriteFormatAttribute(w, BAD_CAST k, "%lld", (long long)v)
                  : xmlTextWriterWriteFormatAttribute(w, BAD_CAST k, "%.3f", v);
}

/* Characters XML 1.0 cannot hold (control bytes but tab and newlines) as '?'. */
static void xml_clean(char *s)
{
    for (unsigned char *p = (unsigned char *)s; *p; p++)
        if (*p < 0x20 && *p != '\t' && *p != '\n' && *p != '\r') *p = '?';
}

static int write_buffer(FILE *f, const void *user)
{
    const xmlBufferPtr b = (xmlBufferPtr)user;
    const size_t n = (size_t)xmlBufferLength(b);
    return fwrite(xmlBufferContent(b), 1, n, f) == n ? 0 : -1;
}

int cli_junit_write(spr__args *a, cli_junit *j, const char *path)
{
    if (!j || !path) return 0;
    int failures = 0, errors = 0, skipped = 0;
    for (int i = 0; i < j->n; i++) {
        failures += j->c[i].status == CLI_JUNIT_FAILURE;
        errors += j->c[i].status == CLI_JUNIT_ERROR;
        skipped += j->c[i].status == CLI_JUNIT_SKIPPED;
        xml_clean(j->c[i].message), xml_clean(j->c[i].text), xml_clean(j->c[i].name), xml_clean(j->c[i].classname);
    }
    const double total = (spr_now_ms() - j->t0) / 1000.0;
    char host[256] = "localhost";
    gethostname(host, sizeof host - 1);
    xmlBufferPtr buf = xmlBufferCreate();
    xmlTextWriterPtr w = buf ? xmlNewTextWriterMemory(buf, 0) : NULL;
    if (!w) { xmlBufferFree(buf); spr__error(a, "--junit: out of memory"); return -1; }
    int r = 0;
    xmlTextWriterSetIndent(w, 1);
    r |= xmlTextWriterStartDocument(w, NULL, "UTF-8", NULL) < 0;
    r |= xmlTextWriterStartElement(w, BAD_CAST "testsuites") < 0;
    r |= xmlTextWriterWriteAttribute(w, BAD_CAST "name", BAD_CAST j->suite) < 0;
    r |= attr_num(w, "tests", j->n, 1) < 0 || attr_num(w, "failures", failures, 1) < 0 || attr_num(w, "errors", errors, 1) < 0 ||
         attr_num(w, "time", total, 0) < 0;
    r |= xmlTextWriterStartElement(w, BAD_CAST "testsuite") < 0;
    r |= xmlTextWriterWriteAttribute(w, BAD_CAST "name", BAD_CAST j->suite) < 0;
    r |= attr_num(w, "tests", j->n, 1) < 0 || attr_num(w, "failures", failures, 1) < 0 || attr_num(w, "errors", errors, 1) < 0 ||
         attr_num(w, "skipped", skipped, 1) < 0 || attr_num(w, "time", total, 0) < 0;
    r |= xmlTextWriterWriteAttribute(w, BAD_CAST "timestamp", BAD_CAST j->stamp) < 0;
    r |= xmlTextWriterWriteAttribute(w, BAD_CAST "hostname", BAD_CAST host) < 0;
    for (int i = 0; i < j->n && !r; i++) {
        const jcase *c = &j->c[i];
        r |= xmlTextWriterStartElement(w, BAD_CAST "testcase") < 0;
        r |= xmlTextWriterWriteAttribute(w, BAD_CAST "classname", BAD_CAST c->classname) < 0;
        r |= xmlTextWriterWriteAttribute(w, BAD_CAST "name", BAD_CAST c->name) < 0;
        r |= attr_num(w, "time", c->seconds, 0) < 0;
        if (c->status != CLI_JUNIT_PASS) {
            static const char *const tag[] = {"", "failure", "error", "skipped"};
            r |= xmlTextWriterStartElement(w, BAD_CAST tag[c->status]) < 0;
            r |= xmlTextWriterWriteAttribute(w, BAD_CAST "message", BAD_CAST c->message) < 0;
            if (c->status != CLI_JUNIT_SKIPPED) r |= xmlTextWriterWriteAttribute(w, BAD_CAST "type", BAD_CAST tag[c->status]) < 0;
            r |= xmlTextWriterWriteString(w, BAD_CAST c->text) < 0;
            r |= xmlTextWriterEndElement(w) < 0;
        } else if (c->text[0]) {
            r |= xmlTextWriterWriteElement(w, BAD_CAST "system-out", BAD_CAST c->text) < 0;
        }
        r |= xmlTextWriterEndElement(w) < 0;
    }
    r |= xmlTextWriterEndDocument(w) < 0;
    xmlFreeTextWriter(w);
    spr_error err = {0};
    if (!r) r = spr__write_atomic(path, write_buffer, buf, &err) != SPR_OK; /* through a temporary file, renamed */
    xmlBufferFree(buf);
    if (r) {
        spr__error(a, "--junit: %s", err.msg[0] ? err.msg : "cannot write the report");
        return -1;
    }
    return 0;
}

FILE *cli_text_begin(cli_text *t)
{
    t->buf = NULL, t->len = 0;
    t->f = open_memstream(&t->buf, &t->len);
    return t->f ? t->f : stdout;
}

const char *cli_text_close(cli_text *t)
{
    if (!t->f) return "";
    fclose(t->f);
    t->f = NULL;
    return t->buf ? t->buf : "";
}

const char *cli_text_end(cli_text *t)
{
    const int kept = t->f != NULL;
    const char *text = cli_text_close(t);
    if (kept) fputs(text, stdout);
    return text;
}

void cli_text_free(cli_text *t)
{
    free(t->buf);
    t->buf = NULL;
}
