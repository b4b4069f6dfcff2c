// In-page side of the harness. render.mjs loads page.html and calls
// window.runHarness(cfg); the viewer-specific code lives in viewer-<name>.js.

// --- Log the blend state of every draw call ------------------------------------
// Wrapping the WebGL2 prototype before any viewer runs lets us report which blend
// functions actually reach the GPU (the viewers' own docs are not always explicit).
const GL = WebGL2RenderingContext;
const enumName = {};
for (const k of ['ZERO', 'ONE', 'SRC_COLOR', 'ONE_MINUS_SRC_COLOR', 'DST_COLOR', 'ONE_MINUS_DST_COLOR',
  'SRC_ALPHA', 'ONE_MINUS_SRC_ALPHA', 'DST_ALPHA', 'ONE_MINUS_DST_ALPHA', 'CONSTANT_COLOR',
  'ONE_MINUS_CONSTANT_COLOR', 'CONSTANT_ALPHA', 'ONE_MINUS_CONSTANT_ALPHA', 'SRC_ALPHA_SATURATE',
  'FUNC_ADD', 'FUNC_SUBTRACT', 'FUNC_REVERSE_SUBTRACT', 'MIN', 'MAX']) enumName[GL[k]] = k;

const blendState = new WeakMap();   // gl -> current blend state (GL defaults initially)
const drawLog = new Map();          // "state + target" -> number of draw calls
const stateOf = (gl) => {
  if (!blendState.has(gl)) blendState.set(gl, { on: false, f: [GL.ONE, GL.ZERO, GL.ONE, GL.ZERO], eq: [GL.FUNC_ADD, GL.FUNC_ADD] });
  return blendState.get(gl);
};
const P = GL.prototype;
const wrap = (name, after) => {
  const orig = P[name];
  P[name] = function (...a) { after(this, a); return orig.apply(this, a); };
};
wrap('enable', (gl, [cap]) => { if (cap === GL.BLEND) stateOf(gl).on = true; });
wrap('disable', (gl, [cap]) => { if (cap === GL.BLEND) stateOf(gl).on = false; });
wrap('blendFunc', (gl, [s, d]) => { stateOf(gl).f = [s, d, s, d]; });
wrap('blendFuncSeparate', (gl, a) => { stateOf(gl).f = a.slice(0, 4); });
wrap('blendEquation', (gl, [e]) => { stateOf(gl).eq = [e, e]; });
wrap('blendEquationSeparate', (gl, a) => { stateOf(gl).eq = a.slice(0, 2); });
for (const d of ['drawArrays', 'drawElements', 'drawArraysInstanced', 'drawElementsInstanced', 'drawRangeElements']) {
  wrap(d, (gl) => {
    const s = stateOf(gl);
    const fbo = gl.getParameter(GL.DRAW_FRAMEBUFFER_BINDING) ? 'offscreen' : 'canvas';
    const key = !s.on ? `blend off -> ${fbo}`
      : `rgb ${s.f.slice(0, 2).map((v) => enumName[v]).join(',')} ${enumName[s.eq[0]]}; ` +
        `alpha ${s.f.slice(2).map((v) => enumName[v]).join(',')} ${enumName[s.eq[1]]} -> ${fbo}`;
    drawLog.set(key, (drawLog.get(key) || 0) + 1);
  });
}

const nextTask = () => new Promise((r) => setTimeout(r, 0));

window.runHarness = async (cfg) => {
  const { width: W, height: H } = cfg.cam;
  const canvas = document.createElement('canvas');
  // Exactly W x H drawing-buffer pixels and W x H CSS pixels (devicePixelRatio is 1).
  canvas.width = W; canvas.height = H;
  canvas.style.width = `${W}px`; canvas.style.height = `${H}px`;
  document.body.appendChild(canvas);

  const { create } = await import(`/viewer-${cfg.viewer}.js`);
  const t0 = performance.now();
  const v = await create(canvas, cfg);   // load + upload the PLY
  await v.ready();                       // the sort for this exact camera has been applied
  const loadMs = performance.now() - t0;

  // Render until two consecutive frames give the same image (async sort results,
  // fades etc. would show up here), yielding to the event loop between frames.
  let prev = null, stableAfter = -1;
  for (let i = 0; i < 30 && stableAfter < 0; i++) {
    v.renderFrame();
    const img = canvas.toDataURL('image/png');
    if (img === prev) stableAfter = i;
    prev = img;
    await nextTask();
  }

  // Timed frames: each one is ended by gl.finish() plus a 1-pixel readPixels, which
  // blocks until the GPU (SwiftShader here) has executed everything for that frame.
  const gl = v.gl, px = new Uint8Array(4), times = [];
  gl.finish();
  for (let i = 0; i < cfg.frames; i++) {
    const a = performance.now();
    v.renderFrame();
    gl.finish();
    gl.readPixels(0, 0, 1, 1, GL.RGBA, GL.UNSIGNED_BYTE, px);
    times.push(performance.now() - a);
    await nextTask();
  }
  const png = canvas.toDataURL('image/png');   // preserveDrawingBuffer is on

  return {
    numSplats: v.numSplats, loadMs, stableAfter, changedWhileTiming: png !== prev,
    frameMs: times.reduce((s, t) => s + t, 0) / Math.max(1, times.length),
    png, info: v.info || {}, contextAttributes: gl.getContextAttributes(),
    drawingBuffer: [gl.drawingBufferWidth, gl.drawingBufferHeight],
    dpr: window.devicePixelRatio, blend: Object.fromEntries(drawLog),
  };
};
window.harnessReady = true;
