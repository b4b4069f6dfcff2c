/* profiles.c — the renderer profile table (SPEC §10.9) as text: each rule's
 * value in words, the Markdown table docs/gaussians.md embeds (a test holds
 * the two equal, so the documentation cannot drift from the code), and JSON
 * for `splatref profiles --json` and Python's splatref.profiles(). */
#include "spr__inspect.h"
#include "spr_profile_diff.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* "2.5e-05", "0.99", "1/255": a float as the table's reader knows it. */
static const char *num(float v, char *b, size_t cap)
{
    if (v == 1.0f / 255.0f) snprintf(b, cap, "1/255");
    else if (v == 0.5f / 255.0f) snprintf(b, cap, "0.5/255");
    else if (v == (float)sqrt(8.0)) snprintf(b, cap, "√8");
    else snprintf(b, cap, "%.6g", v);
    return b;
}

void spr__profile_rule_text(const spr_gauss_profile *p, int rule, char *out, size_t cap)
{
    char a[32], b[32], c[32];
    out[0] = 0;
    switch (rule) {
    case 0: snprintf(out, cap, "%s", spr_algo_name(p->skeleton)); break;
    case 1: {
        size_t o = 0;
        if (p->cull.near < 0.0f) o += (size_t)snprintf(out + o, cap - o, "t.z %s the camera's near plane", p->cull.near_lt ? "<" : "≤");
        else o += (size_t)snprintf(out + o, cap - o, "t.z %s %s", p->cull.near_lt ? "<" : "≤", num(p->cull.near, a, sizeof a));
        if (p->cull.clip_k > 0.0f && o < cap) o += (size_t)snprintf(out + o, cap - o, "; \\|x\\|, \\|y\\| > %s·w", num(p->cull.clip_k, a, sizeof a));
        if (o < cap) snprintf(out + o, cap - o, "; det %s 0", p->cull.det_le ? "≤" : "=");
        break;
    }
    case 2:
        snprintf(out, cap, "%s%s", p->tan_clamp == 0 ? "none" : p->tan_clamp == 1 ? "±1.3·tan(fov/2)" : "−(cx/fx + 0.3·tan) … (W − cx)/fx + 0.3·tan",
                 p->camera.centre ? "; the principal point ignored: cx = W/2, cy = H/2" : "");
        break;
    case 3:
        snprintf(out, cap, "+%s; %s o·%s", num(p->dilation.eps2d, a, sizeof a), p->dilation.when == SPR_GCOMP_ALWAYS ? "always" : "--gauss-aa:",
                 p->dilation.form == SPR_GCOMP_ROOT_OF_MAX ? (snprintf(b, sizeof b, "√max(%s, det₀/det)", num(p->dilation.floor, c, sizeof c)), b)
                                                           : (snprintf(b, sizeof b, "max(%s, √(det₀/det))", num(p->dilation.floor, c, sizeof c)), b));
        break;
    case 4: {
        const float k = (float)sqrt(p->extent.k2);
        size_t o = 0;
        if (p->extent.kind == SPR_GEXT_SQUARE)
            o += (size_t)snprintf(out, cap, "ceil(%s·√λmax), λ floor %s; tiles trunc", num(k, a, sizeof a), num(p->extent.lambda_min, b, sizeof b));
        else if (p->extent.kind == SPR_GEXT_AXES) o += (size_t)snprintf(out, cap, "per axis ceil(%s·√Σ'aa); tiles floor/ceil", num(k, a, sizeof a));
        else if (p->extent.kind == SPR_GEXT_BOX)
            o += (size_t)snprintf(out, cap, "pixel box floor/ceil(m ∓ %s·√Σ'aa) ± %s px, no tiles of its own: pixels outside skip it", num(k, a, sizeof a),
                                  num(p->extent.pad_px, b, sizeof b));
        else
            o += (size_t)snprintf(out, cap, "quad %s·√λ ≤ %s%s px, λ floor %s", num(k, a, sizeof a), num(p->extent.cap_px, b, sizeof b),
                                  p->extent.cap_view ? ", W, H" : "", num(p->extent.lambda_min, c, sizeof c));
        if (p->skeleton == SPR_ALGO_GAUSS_BLEND && o < cap) o += (size_t)snprintf(out + o, cap - o, "; cut at power < −k²/2");
        if (p->extent.falloff && o < cap) o += (size_t)snprintf(out + o, cap - o, ", falloff renormalised to 0 there");
        if (p->extent.min_px > 0.0f && o < cap) snprintf(out + o, cap - o, "; dropped under %s px", num(p->extent.min_px, a, sizeof a));
        break;
    }
    case 5:
        snprintf(out, cap, "%s; %s", p->alpha.cap >= 1.0f ? "no cap" : (snprintf(a, sizeof a, "cap %s", num(p->alpha.cap, b, sizeof b)), a),
                 p->alpha.floor > 0.0f ? (snprintf(c, sizeof c, "skip < %s", num(p->alpha.floor, b, sizeof b)), c) : "no floor");
        break;
    case 6:
        if (p->stop.t_min > 0.0f) snprintf(out, cap, "T·(1 − α) %s %s", p->stop.le ? "≤" : "<", num(p->stop.t_min, a, sizeof a));
        else snprintf(out, cap, "none");
        break;
    case 7:
        switch (p->order.key) {
        case SPR_GKEY_TILE_DEPTH: snprintf(out, cap, "per tile, float t.z"); break;
        case SPR_GKEY_DISTANCE: snprintf(out, cap, "global, \\|μ − eye\\| (double)"); break;
        case SPR_GKEY_VIEW_Z: snprintf(out, cap, "global, float t.z"); break;
        case SPR_GKEY_TILE_GLDEPTH:
            snprintf(out, cap, "per tile (its global sort), float OpenGL depth z·(1/max(w, 1e-6)) of near %s, far %s", num(p->order.znear, a, sizeof a),
                     num(p->order.zfar, b, sizeof b));
            break;
        default: snprintf(out, cap, "global, Σ round(1000·μ)·trunc(1000·clip-z row) in %d-bit buckets of the frame's range", p->order.bits);
        }
        break;
    case 8:
        snprintf(out, cap, "%s", p->blend == SPR_GBLEND_UNDER ? "front to back" : p->blend == SPR_GBLEND_PREMUL ? "back to front, premultiplied" : "back to front, straight");
        break;
    case 9: {
        size_t o = (size_t)snprintf(out, cap, "SH ≤ %d", p->colour.sh_max);
        static const char *const q8[] = {"", "rounded", "floored", "rounded, then halved: steps of 2/255"};
        if (p->colour.dc8 && o < cap) o += (size_t)snprintf(out + o, cap - o, "; DC + 0.5 in 8 bits (%s)", q8[p->colour.dc8]);
        if (p->colour.op8 && o < cap) o += (size_t)snprintf(out + o, cap - o, "; opacity in 8 bits (%s)", q8[p->colour.op8]);
        if (p->colour.post8 && o < cap) o += (size_t)snprintf(out + o, cap - o, "; the colour after SH in 8 bits (%s)", q8[p->colour.post8]);
        if (o < cap) o += (size_t)snprintf(out + o, cap - o, "; %s", p->colour.clamp_hi ? "[0, 1]" : "≥ 0");
        if (p->colour.scale8 && o < cap)
            o += (size_t)snprintf(out + o, cap - o, "; σ in a log 8-bit code (%s)", p->colour.scale8 == SPR_GSCALE8_SPARK ? "Spark's" : "PlayCanvas's");
        if (p->colour.pos16 && o < cap) snprintf(out + o, cap - o, "; centres as half floats, then relative to the eye");
        break;
    }
    default: break;
    }
}

void spr__profiles_markdown(FILE *f)
{
    fprintf(f, "| profile | algorithm |");
    for (int r = 1; r <= 9; r++) fprintf(f, " %s |", spr__gauss_rule_names[r]);
    fprintf(f, " renderer, version, source |\n|---|---|");
    for (int r = 1; r <= 9; r++) fprintf(f, "---|");
    fprintf(f, "---|\n");
    for (int i = 0; i < spr_gauss_profile_count(); i++) {
        const spr_gauss_profile *p = spr_gauss_profile_at(i);
        fprintf(f, "| `%s` |", p->name);
        for (int r = 0; r <= 9; r++) {
            char t[256];
            spr__profile_rule_text(p, r, t, sizeof t);
            fprintf(f, " %s |", t);
        }
        fprintf(f, " %s %s: `%s` |\n", p->renderer, p->version, p->source);
    }
}

cJSON *spr__profiles_json(void)
{
    cJSON *arr = cJSON_CreateArray();
    for (int i = 0; arr && i < spr_gauss_profile_count(); i++) {
        const spr_gauss_profile *p = spr_gauss_profile_at(i);
        cJSON *o = cJSON_CreateObject(), *rules = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "name", p->name);
        cJSON_AddStringToObject(o, "algo", spr_algo_name(p->skeleton));
        cJSON_AddStringToObject(o, "renderer", p->renderer);
        cJSON_AddStringToObject(o, "version", p->version);
        cJSON_AddStringToObject(o, "source", p->source);
        for (int r = 1; r <= 9; r++) {
            char t[256];
            spr__profile_rule_text(p, r, t, sizeof t);
            cJSON_AddStringToObject(rules, spr__gauss_rule_names[r], t);
        }
        cJSON_AddItemToObject(o, "rules", rules);
        cJSON_AddItemToArray(arr, o);
    }
    return arr;
}
