// @sparkjsdev/spark: a SparkRenderer + SplatMesh in a plain three.js scene.
import * as THREE from 'three';
import { SparkRenderer, SplatMesh } from '@sparkjsdev/spark';
import { makeRenderer, makeCamera, threeVersion } from './three-common.js';

export async function create(canvas, cfg) {
  const renderer = makeRenderer(canvas, cfg.cam);
  const camera = makeCamera(cfg.cam);
  const scene = new THREE.Scene();
  // autoUpdate off: Spark would otherwise re-generate/re-sort from inside render();
  // we call spark.update() ourselves and await its sort.
  // Blur: Spark's own default (blurAmount 0.3 with its opacity compensation, preBlurAmount 0),
  // the image Spark means to draw and the one splatref's `spark` profile follows.
  const spark = new SparkRenderer({ renderer, autoUpdate: false });
  scene.add(spark);

  // SplatMesh gets an identity transform: the PLY's coordinates as they are (Spark's
  // PLY decoder does not flip axes; its examples rotate y-down scenes themselves).
  const mesh = new SplatMesh({ url: cfg.plyUrl, fileType: 'ply' });
  await mesh.initialized;
  if (cfg.sh != null) { mesh.maxSh = cfg.sh; mesh.updateGenerator(); }   // default maxSh = 3
  scene.add(mesh);

  return {
    gl: renderer.getContext(),
    numSplats: mesh.numSplats,
    info: {
      three: threeVersion, shDegree: Math.min(mesh.maxSh, mesh.splats.getNumSh()),
      sortRadial: spark.sortRadial, minAlpha: spark.minAlpha, preBlurAmount: spark.preBlurAmount, blurAmount: spark.blurAmount,
      maxStdDev: spark.maxStdDev, focalAdjustment: spark.focalAdjustment, clipXY: spark.clipXY,
      premultipliedAlpha: spark.premultipliedAlpha, outputColorSpace: renderer.outputColorSpace,
    },
    async ready() {
      renderer.render(scene, camera);        // sets Spark's render size from the canvas
      await spark.update({ scene, camera }); // generate splats for this view + sort (worker)
      for (let i = 0; spark.sorting || spark.sortDirty; i++) {   // a chained re-sort, if any
        if (i > 30000) throw new Error('spark: sort did not finish');
        await new Promise((r) => setTimeout(r, 2));
      }
      const c = new THREE.Vector3(...cfg.cam.eye);
      if (spark.sortedCenter.distanceTo(c) > 1e-4) throw new Error('spark: sorted for another viewpoint');
      this.info.activeSplats = spark.activeSplats;
    },
    renderFrame() {
      renderer.render(scene, camera);
    },
  };
}
