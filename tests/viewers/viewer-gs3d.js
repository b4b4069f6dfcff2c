// @mkkellogg/gaussian-splats-3d: its Viewer, driven frame by frame by us
// (selfDrivenMode off) with our own three.js renderer and camera.
import * as GS from '@mkkellogg/gaussian-splats-3d';
import { makeRenderer, makeCamera, threeVersion } from './three-common.js';

const until = async (cond, what, ms = 60000) => {
  for (const t0 = performance.now(); !cond();) {
    if (performance.now() - t0 > ms) throw new Error(`gs3d: timed out waiting for ${what}`);
    await new Promise((r) => setTimeout(r, 2));
  }
};

export async function create(canvas, cfg) {
  if (cfg.sh != null && !(cfg.sh >= 0 && cfg.sh <= 2)) throw new Error('gs3d supports SH degree 0..2 only');
  const renderer = makeRenderer(canvas, cfg.cam);
  const camera = makeCamera(cfg.cam);
  const viewer = new GS.Viewer({
    renderer, camera,                 // external: the viewer neither resizes nor moves them
    selfDrivenMode: false,            // no requestAnimationFrame loop; we call update()/render()
    useBuiltInControls: false,
    ignoreDevicePixelRatio: true,
    gpuAcceleratedSort: false,        // CPU (WASM) sort in a web worker
    sharedMemoryForWorkers: false,    // no SharedArrayBuffer, so no COOP/COEP headers needed
    // integerBasedSort: left at its default (true)
    antialiased: false,
    sphericalHarmonicsDegree: cfg.sh ?? 0,        // gs3d's default is 0
    sceneRevealMode: GS.SceneRevealMode.Instant,  // default fades splats in over time
    renderMode: GS.RenderMode.Always,
    logLevel: GS.LogLevel.None,
  });
  await viewer.addSplatScene(cfg.plyUrl, {
    format: GS.SceneFormat.Ply,
    showLoadingUI: false,
    progressiveLoad: false,
    // Default is 1 (of 255). 0 keeps every splat at load; note SplatScene still
    // uses `|| 1`, i.e. colours with alpha < 1/255 are zeroed when uploaded.
    splatAlphaRemovalThreshold: 0,
    // No position/rotation/scale: the PLY's coordinates are used as they are
    // (gs3d's INRIA PLY parser does no axis flip).
  });

  return {
    gl: renderer.getContext(),
    numSplats: viewer.splatMesh.getSplatCount(),
    info: {
      three: threeVersion, shDegree: viewer.sphericalHarmonicsDegree,
      integerBasedSort: viewer.integerBasedSort,
      outputColorSpace: renderer.outputColorSpace,
    },
    async ready() {
      // addSplatScene already waited for a sort made with this camera; force one more
      // full sort from this exact pose and wait until the worker's result is applied.
      await until(() => !viewer.sortRunning, 'initial sort');
      viewer.runSplatSort(true, true);
      await until(() => !viewer.sortRunning, 'forced sort');
      this.info.splatsSorted = viewer.splatRenderCount;
    },
    renderFrame() {
      viewer.update();   // no re-sort: the camera has not moved since the last sort
      viewer.render();
    },
  };
}
