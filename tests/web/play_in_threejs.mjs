// Plays a GLB's first animation as a game does with three.js (npm three in web/node_modules): an AnimationMixer,
// every vertex skinned and morphed on the CPU (Mesh.getVertexPosition; packed files decoded by three.js's meshopt
// decoder), frame k at k / FPS, against the PC2 of the same bake. Prints one JSON object: frames, vertices, and
// the RMS and worst vertex distance over every frame, as fractions of the rest mesh's bounding-box diagonal (from
// the OBJ the bake wrote beside the PC2). The same measure as play_in_blender.py.
// Usage: node play_in_threejs.mjs NODE_MODULES_DIR FILE.glb CACHE.pc2 REST.obj FPS
import fs from 'fs';
import path from 'path';
import { pathToFileURL } from 'url';

const [modules, glb, pc2, restObj, fpsText] = process.argv.slice(2);
const three = path.resolve(modules, 'three');
const THREE = await import(pathToFileURL(path.join(three, 'build/three.module.js')));
const { GLTFLoader } = await import(pathToFileURL(path.join(three, 'examples/jsm/loaders/GLTFLoader.js')));
const { MeshoptDecoder } = await import(pathToFileURL(path.join(three, 'examples/jsm/libs/meshopt_decoder.module.js')));
const fps = Number(fpsText);

const cache = fs.readFileSync(pc2);
if (cache.toString('latin1', 0, 11) !== 'POINTCACHE2') throw new Error(`${pc2}: not a PC2 file`);
const points = cache.readInt32LE(16);
const samples = cache.readInt32LE(28);
const expected = (s, i, c) => cache.readFloatLE(32 + 4 * (3 * (points * s + i) + c));

const low = [Infinity, Infinity, Infinity];
const high = [-Infinity, -Infinity, -Infinity];
for (const line of fs.readFileSync(restObj, 'utf8').split('\n')) {
  if (!line.startsWith('v ')) continue;
  const p = line.split(/\s+/).slice(1, 4).map(Number);
  for (let c = 0; c < 3; c++) { low[c] = Math.min(low[c], p[c]); high[c] = Math.max(high[c], p[c]); }
}
const diagonal = Math.hypot(high[0] - low[0], high[1] - low[1], high[2] - low[2]);

const bytes = fs.readFileSync(glb);
const gltf = await new Promise((resolve, reject) =>
  new GLTFLoader().setMeshoptDecoder(MeshoptDecoder).parse(bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength), '', resolve, reject));
const mixer = new THREE.AnimationMixer(gltf.scene);
mixer.clipAction(gltf.animations[0]).play();
const meshes = [];
gltf.scene.traverse((o) => { if (o.isMesh) meshes.push(o); });

let sumSquares = 0;
let worst = 0;
let count = 0;
const v = new THREE.Vector3();
for (let s = 0; s < samples; s++) {
  mixer.setTime(s / fps);
  gltf.scene.updateMatrixWorld(true);
  let i = 0;
  for (const m of meshes) {
    if (m.isSkinnedMesh) m.skeleton.update();
    for (let k = 0; k < m.geometry.attributes.position.count; k++, i++) {
      if (i >= points) break;
      m.getVertexPosition(k, v);
      v.applyMatrix4(m.matrixWorld);
      const d = Math.hypot(v.x - expected(s, i, 0), v.y - expected(s, i, 1), v.z - expected(s, i, 2));
      sumSquares += d * d;
      worst = Math.max(worst, d);
      count++;
    }
  }
  if (i !== points) {
    console.log(JSON.stringify({ error: `${i} vertices played, ${points} in the cache` }));
    process.exit(0);
  }
}
console.log(JSON.stringify({ frames: samples, vertices: points, rms: Math.sqrt(sumSquares / count) / diagonal, worst: worst / diagonal }));
