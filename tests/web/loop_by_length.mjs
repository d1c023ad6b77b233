// Plays a GLB's first animation the way a game does with three.js (npm three in web/node_modules): an
// AnimationMixer looping the clip by its length, every vertex skinned and morphed on the CPU
// (Mesh.getVertexPosition; packed files decoded by three.js's meshopt decoder), sampled at k / fps for two cycles. Prints one JSON object: the clip's duration,
// the frames in one cycle (duration × fps), each sample-to-sample step (RMS over the vertices, metres) and
// how far the sample one cycle on is from the first.
// Usage: node loop_by_length.mjs NODE_MODULES_DIR FILE.glb FPS
import fs from 'fs';
import path from 'path';
import { pathToFileURL } from 'url';

const three = path.resolve(process.argv[2], 'three');
const THREE = await import(pathToFileURL(path.join(three, 'build/three.module.js')));
const { GLTFLoader } = await import(pathToFileURL(path.join(three, 'examples/jsm/loaders/GLTFLoader.js')));
const { MeshoptDecoder } = await import(pathToFileURL(path.join(three, 'examples/jsm/libs/meshopt_decoder.module.js')));
const bytes = fs.readFileSync(process.argv[3]);
const fps = Number(process.argv[4]);
const gltf = await new Promise((resolve, reject) =>
  new GLTFLoader().setMeshoptDecoder(MeshoptDecoder).parse(bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength), '', resolve, reject));
const clip = gltf.animations[0];
const mixer = new THREE.AnimationMixer(gltf.scene);
mixer.clipAction(clip).setLoop(THREE.LoopRepeat, Infinity).play();
const meshes = [];
gltf.scene.traverse((o) => { if (o.isMesh) meshes.push(o); });
const sample = (t) => {
  mixer.setTime(t);
  gltf.scene.updateMatrixWorld(true);
  const out = [];
  const v = new THREE.Vector3();
  for (const m of meshes) {
    if (m.isSkinnedMesh) m.skeleton.update();
    for (let i = 0; i < m.geometry.attributes.position.count; i++) {
      m.getVertexPosition(i, v);
      v.applyMatrix4(m.matrixWorld);
      out.push(v.x, v.y, v.z);
    }
  }
  return out;
};
const rms = (a, b) => {
  let s = 0;
  for (let i = 0; i < a.length; i++) s += (a[i] - b[i]) ** 2;
  return Math.sqrt(s / (a.length / 3));
};
const frames = Math.round(clip.duration * fps);
const first = sample(0);
const steps = [];
let previous = first;
let cycle = 0;
for (let k = 1; k <= 2 * frames; k++) {
  const current = sample(k / fps);
  steps.push(rms(current, previous));
  if (k === frames) cycle = rms(current, first);
  previous = current;
}
console.log(JSON.stringify({ duration: clip.duration, frames, steps, cycle }));
