// Renderer and camera set-up shared by the two three.js based viewers (gs3d, spark).
import * as THREE from 'three';

export function makeRenderer(canvas, cam) {
  const renderer = new THREE.WebGLRenderer({
    canvas,
    antialias: false,
    alpha: false,                  // opaque canvas: the clear colour is the background
    preserveDrawingBuffer: true,   // so toDataURL() can read the last frame
    powerPreference: 'high-performance',
  });
  renderer.setPixelRatio(1);
  renderer.setSize(cam.width, cam.height, false);
  // three.js treats colours as sRGB and converts to its linear working space;
  // tagging the background as sRGB makes the clear write exactly these values
  // to the (sRGB) canvas. renderer.outputColorSpace stays at its default (sRGB).
  renderer.setClearColor(new THREE.Color().setRGB(...cam.background, THREE.SRGBColorSpace), 1);
  renderer.toneMapping = THREE.NoToneMapping;   // the default, stated explicitly
  return renderer;
}

// OpenGL look-at camera: at eye, looking at target, with the given up vector.
export function makeCamera(cam) {
  const camera = new THREE.PerspectiveCamera(cam.fovy_deg, cam.width / cam.height, cam.near, cam.far);
  camera.position.set(...cam.eye);
  camera.up.set(...cam.up);
  camera.lookAt(...cam.target);
  camera.updateMatrixWorld(true);
  return camera;
}

export const threeVersion = THREE.REVISION;
