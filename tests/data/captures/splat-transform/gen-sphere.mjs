// gen-sphere.mjs: a splat-transform generator for the unit sphere of
// tests/data/captures/splat-transform/: 600 flat Gaussians on a Fibonacci
// lattice of the unit sphere, tangent to it (sigma 0.08 along the surface,
// 0.004 across), SH DC colour (0.25, 0.5, 0.85), opacity 0.9, and small
// degree-1..3 coefficients (so view-dependent colour is exercised).
// splat-transform writes every file from it (see PROVENANCE.md).
const C0 = 0.28209479177387814;
const N = 600;
const logit = (p) => Math.log(p / (1 - p));
const golden = Math.PI * (3 - Math.sqrt(5));
const rest = [];
for (let k = 0; k < 45; k++) rest.push('f_rest_' + k);
class Sphere {
    constructor() {
        this.count = N;
        this.columnNames = ['x', 'y', 'z', 'scale_0', 'scale_1', 'scale_2', 'rot_0', 'rot_1', 'rot_2', 'rot_3',
            'f_dc_0', 'f_dc_1', 'f_dc_2', 'opacity', ...rest];
    }
    getRow(i, row) {
        const z = 1 - (2 * (i + 0.5)) / N, r = Math.sqrt(1 - z * z), phi = golden * i;
        const n = [r * Math.cos(phi), r * Math.sin(phi), z];
        row.x = n[0];
        row.y = n[1];
        row.z = n[2];
        row.scale_0 = Math.log(0.08);
        row.scale_1 = Math.log(0.08);
        row.scale_2 = Math.log(0.004);
        // the rotation taking local z to n: axis z x n, angle acos(n.z)
        const ax = [-n[1], n[0], 0], al = Math.hypot(ax[0], ax[1]);
        const ang = Math.acos(Math.max(-1, Math.min(1, n[2])));
        const s = Math.sin(ang / 2);
        row.rot_0 = Math.cos(ang / 2);
        row.rot_1 = al > 0 ? (ax[0] / al) * s : 0;
        row.rot_2 = al > 0 ? (ax[1] / al) * s : 0;
        row.rot_3 = 0;
        row.f_dc_0 = (0.25 - 0.5) / C0;
        row.f_dc_1 = (0.5 - 0.5) / C0;
        row.f_dc_2 = (0.85 - 0.5) / C0;
        row.opacity = logit(0.9);
        for (let k = 0; k < 45; k++) row['f_rest_' + k] = 0.08 * Math.sin(0.7 * k + 0.013 * i);
    }
}
export class Generator {
    static create() { return new Sphere(); }
}
