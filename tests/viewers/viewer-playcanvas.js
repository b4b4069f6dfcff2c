// PlayCanvas engine: a 'gsplat' asset (its PLY parser) on an entity with a gsplat
// component, rendered by a camera entity. We tick the app ourselves.
import * as pc from 'playcanvas';

// PlayCanvas has no "SH degree" option: it uses every band in the file. For --sh D
// we drop the higher bands from the parsed data before it is uploaded. f_rest_* is
// channel-major (all R coefficients, then G, then B), so the kept ones are renumbered.
function truncateSh(gsplatData, degree) {
  const props = gsplatData.getElement('vertex').properties;
  const rest = props.filter((p) => p.name.startsWith('f_rest_'));
  const nFile = rest.length / 3, nKeep = (degree + 1) ** 2 - 1;
  if (nKeep >= nFile) return;
  const byName = Object.fromEntries(rest.map((p) => [p.name, p]));
  const kept = [];
  for (let c = 0; c < 3; c++) {
    for (let j = 0; j < nKeep; j++) kept.push({ ...byName[`f_rest_${c * nFile + j}`], name: `f_rest_${c * nKeep + j}` });
  }
  const others = props.filter((p) => !p.name.startsWith('f_rest_'));
  props.length = 0;
  props.push(...others, ...kept);
}

export async function create(canvas, cfg) {
  const { cam } = cfg;
  const app = new pc.Application(canvas, {
    devtools: false,
    graphicsDeviceOptions: {
      deviceTypes: [pc.DEVICETYPE_WEBGL2], antialias: false,
      alpha: false,                  // opaque canvas: the clear colour is the background
      preserveDrawingBuffer: true,   // so toDataURL() can read the last frame
      powerPreference: 'high-performance',
    },
  });
  app.graphicsDevice.maxPixelRatio = 1;
  app.setCanvasFillMode(pc.FILLMODE_NONE, cam.width, cam.height);
  app.setCanvasResolution(pc.RESOLUTION_FIXED, cam.width, cam.height);
  // No requestAnimationFrame loop: renderFrame() calls app.tick() once per frame.
  app.requestAnimationFrame = () => {};
  app.start();

  const camera = new pc.Entity('camera');
  camera.addComponent('camera', {
    clearColor: new pc.Color(...cam.background, 1),
    fov: cam.fovy_deg, horizontalFov: false,       // vertical field of view
    nearClip: cam.near, farClip: cam.far,
    // Default is TONEMAP_LINEAR, which gsplat output passes through (decode gamma,
    // x exposure 1, encode gamma). NONE skips that round trip. Gamma stays sRGB.
    toneMapping: pc.TONEMAP_NONE,
  });
  app.root.addChild(camera);
  camera.setPosition(...cam.eye);
  camera.lookAt(new pc.Vec3(...cam.target), new pc.Vec3(...cam.up));  // looks down -Z, as OpenGL

  // Readiness: 'frame:ready' says the frame shows the latest world state with its
  // sort applied; 'gsplat:sorted' counts results coming back from the sort worker.
  let ready = false, sorts = 0;
  app.systems.gsplat.on('frame:ready', (c, layer, isReady, loading) => { ready = isReady && !loading; });
  app.scene.on('gsplat:sorted', () => { sorts++; });

  const asset = new pc.Asset('input.ply', 'gsplat', { url: cfg.plyUrl });
  if (cfg.sh != null) asset.on('load:data', (data) => truncateSh(data, cfg.sh));
  await new Promise((resolve, reject) => {
    asset.once('load', resolve);
    asset.once('error', reject);
    app.assets.add(asset);
    app.assets.load(asset);
  });
  // Identity transform: the PLY's coordinates as they are (PlayCanvas' PLY parser
  // does not flip; its examples rotate y-down scenes by 180 deg about X themselves).
  const splat = new pc.Entity('splat');
  splat.addComponent('gsplat', { asset });
  app.root.addChild(splat);

  const gl = app.graphicsDevice.gl;
  return {
    gl,
    numSplats: asset.resource.numSplats ?? asset.resource.gsplatData?.numSplats,
    info: {
      unified: splat.gsplat.unified, shBands: asset.resource.shBands ?? asset.resource.gsplatData?.shBands,
      renderer: app.scene.gsplat.currentRenderer, radialSorting: app.scene.gsplat.radialSorting,
      alphaClipForward: app.scene.gsplat.alphaClipForward, minPixelSize: app.scene.gsplat.minPixelSize,
      minContribution: app.scene.gsplat.minContribution, antiAlias: app.scene.gsplat.antiAlias,
      dataFormat: app.scene.gsplat.dataFormat, gammaCorrection: camera.camera.gammaCorrection,
    },
    async ready() {
      for (let i = 0; !(ready && sorts > 0); i++) {
        if (i > 3000) throw new Error('playcanvas: no sorted frame:ready');
        app.tick(performance.now());
        await new Promise((r) => setTimeout(r, 5));
      }
      app.tick(performance.now());   // apply any result that arrived since
      this.info.sortsReceived = sorts;
    },
    renderFrame() {
      app.tick(performance.now());
    },
  };
}
