/* gl_splat.vert — one instanced quad per splat over its conservative pixel
 * rectangle (spr_splat_pixel_rect, computed on the host).  The quad's edges
 * lie on pixel boundaries, half a pixel from any sampled centre, so rounding
 * here cannot change coverage; coverage is decided per pixel in
 * gl_splat.frag.  Per-splat data goes on as flat varyings (PARITY.md rule 4). */
layout(location = 0) in ivec4 i_rect;   /* x0 y0 x1 y1, inclusive pixels */
layout(location = 1) in vec4 i_pr;      /* centre, radius */
layout(location = 2) in vec4 i_na;      /* normal, opacity */
layout(location = 3) in vec4 i_c;       /* colour */
layout(location = 4) in uint i_id;
layout(location = 5) in uint i_seq;     /* position in the draw's submission order (pixel history) */
layout(location = 6) in vec4 i_e;       /* ellipse: major axis u, minor radius (spr_ray_ellipse) */
uniform vec2 u_size;
flat out vec4 v_pr;
flat out vec4 v_na;
flat out vec4 v_c;
flat out vec4 v_e;
flat out uint v_id;
flat out uint v_seq;
void main()
{
    float x = float((gl_VertexID & 1) != 0 ? i_rect.z + 1 : i_rect.x);
    float y = float((gl_VertexID & 2) != 0 ? i_rect.w + 1 : i_rect.y);
    gl_Position = vec4(x / u_size.x * 2.0 - 1.0, y / u_size.y * 2.0 - 1.0, 0.0, 1.0);
    v_pr = i_pr;
    v_na = i_na;
    v_c = i_c;
    v_e = i_e;
    v_id = i_id;
    v_seq = i_seq;
}
