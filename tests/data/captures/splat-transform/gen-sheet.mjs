// gen-sheet.mjs: a splat-transform generator (its `.mjs` input, "Generators
// (Beta)" in its README) for the flat red sheet of tests/data/captures/
// splat-transform/: 16 x 16 Gaussians in the plane z = 0 covering the square
// [-1, 1]^2, each with sigma 0.12 x 0.08 in the plane (turned 30 degrees about
// z, so a reader that misorders the quaternion tilts them out of the plane)
// and 0.001 across it, SH DC colour (0.9, 0.1, 0.1), opacity 0.95.
// splat-transform writes every file from it (see PROVENANCE.md); this script
// only says what the scene is.
const C0 = 0.28209479177387814;
const N = 16;
const logit = (p) => Math.log(p / (1 - p));
const half = (30 * Math.PI) / 180 / 2;
class Sheet {
    constructor() {
        this.count = N * N;
        this.columnNames = ['x', 'y', 'z', 'scale_0', 'scale_1', 'scale_2', 'rot_0', 'rot_1', 'rot_2', 'rot_3',
            'f_dc_0', 'f_dc_1', 'f_dc_2', 'opacity'];
    }
    getRow(i, row) {
        const a = i % N, b = Math.floor(i / N);
        row.x = -1 + (a + 0.5) * (2 / N);
        row.y = -1 + (b + 0.5) * (2 / N);
        row.z = 0;
        row.scale_0 = Math.log(0.12);
        row.scale_1 = Math.log(0.08);
        row.scale_2 = Math.log(0.001);
        row.rot_0 = Math.cos(half); // w
        row.rot_1 = 0;
        row.rot_2 = 0;
        row.rot_3 = Math.sin(half); // z
        row.f_dc_0 = (0.9 - 0.5) / C0;
        row.f_dc_1 = (0.1 - 0.5) / C0;
        row.f_dc_2 = (0.1 - 0.5) / C0;
        row.opacity = logit(0.95);
    }
}
export class Generator {
    static create() { return new Sheet(); }
}
