// SoftTouch clip preview: plays an exported clip in a browser the way a game engine would, with three.js
// (docs/formats.md, "Preview page"). `softtouch-cli preview CLIP --out DIR` writes DIR/index.html: this
// script, three.js's modules (through an import map of data: URLs, so the page opens from disk with no
// server), the clip's files in base64 and the shipped engine shaders (io/shaders/) in one file.
//
//   skinned, morph: three.js's own glTF loader, skinning and morph targets (AnimationMixer)
//   vat:            the shipped io/shaders/vat_deform.glsl on the EXR textures
//   lattice:        the shipped io/shaders/lattice_deform.glsl, its WebGL 2 form (LATTICE_NODE_TEXTURE)
//
// Address options (after '#', joined by '&'): frame=N shows frame N and stops (frame=A,B,... shows each in
// turn); until=T plays from the start and stops on the frame reached T seconds in (until=T1,T2,... stops at
// each in turn and plays on between them; after frame= it starts from the beginning); tick=S: S seconds a
// step on a timer, not the clock; size=WxH draws at that size; matte draws a white silhouette on black;
// readback writes each picture shown at a stop into <pre id="readback">, one line each: the frame's label, a
// tab, the canvas as a PNG data URL. The page's title becomes "ready" once the last stop is drawn
// (tests/web/test_preview.cpp reads it with headless Chromium: one browser start for every check of a clip).

import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';
import { EXRLoader } from 'three/addons/loaders/EXRLoader.js';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

const clip = JSON.parse(document.getElementById('softtouch-clip').textContent);
const options = new URLSearchParams(location.hash.slice(1));
const listOption = (name) => (options.has(name) ? options.get(name).split(',') : []);
const stillFrames = listOption('frame').map((f) => Math.max(0, Math.min(clip.frames - 1, parseInt(f, 10) || 0)));
const playStops = listOption('until').map((t) => Math.max(0, Number(t) || 0)).sort((a, b) => a - b);
const stops = stillFrames.length > 0 || playStops.length > 0;
const tick = options.has('tick') ? Math.max(0, Number(options.get('tick')) || 0) : 0;
const matte = options.has('matte');
const readback = options.has('readback');
// size=WxH draws at that size whatever the window (a headless browser's window includes its frame).
const fixedSize = /^(\d+)x(\d+)$/.exec(options.get('size') || '');
const viewWidth = () => (fixedSize ? Number(fixedSize[1]) : window.innerWidth);
const viewHeight = () => (fixedSize ? Number(fixedSize[2]) : window.innerHeight);

function fail(error) {
    const message = error && error.message ? error.message : String(error);
    document.getElementById('status').textContent = 'Cannot play ' + clip.name + ': ' + message;
    document.title = 'error: ' + message;
}

// Every embedded file decoded once (the loaders only read it), and as a blob URL, so a .gltf's external
// buffers resolve by name.
const decoded = {};
for (const [name, base64] of Object.entries(clip.files)) {
    const text = atob(base64);
    const bytes = new Uint8Array(text.length);
    for (let i = 0; i < text.length; ++i) bytes[i] = text.charCodeAt(i);
    decoded[name] = bytes.buffer;
}
const fileBytes = (name) => decoded[name];
const manager = new THREE.LoadingManager();
const blobUrls = {};
for (const name of Object.keys(decoded))
    blobUrls[name] = URL.createObjectURL(new Blob([decoded[name]]));
manager.setURLModifier((url) => blobUrls[url.split('/').pop()] || url);

function loadGltf(name) {
    // bake --compress packs GLBs with EXT_meshopt_compression, as games ship them.
    const loader = new GLTFLoader(manager).setMeshoptDecoder(MeshoptDecoder);
    const data = name.endsWith('.gltf') ? new TextDecoder().decode(fileBytes(name)) : fileBytes(name);
    return new Promise((resolve, reject) => loader.parse(data, '', resolve, reject));
}

// The shipped GLSL 4.30 sources as WebGL 2 (GLSL ES 3.00) shaders: three.js's GLSL3 mode writes the
// #version line; the sources themselves keep to what both languages accept.
function webglSource(source, defines) {
    return defines.map((d) => '#define ' + d + '\n').join('') +
        'precision highp float;\nprecision highp int;\nprecision highp sampler2D;\n' +
        source.replace(/^#version[^\n]*\n/, '');
}

const fragmentShader = `precision highp float;
in vec3 vNormal;
out vec4 fragColour;
uniform vec3 uColour;
uniform bool uMatte;
void main() {
    if (uMatte) { fragColour = vec4(1.0); return; }
    vec3 n = normalize(vNormal);
    if (!gl_FrontFacing) n = -n;
    float key = max(dot(n, normalize(vec3(-0.5, 0.7, 0.6))), 0.0);
    float fill = 0.35 * max(dot(n, normalize(vec3(0.8, -0.1, 0.4))), 0.0);
    fragColour = vec4(min(uColour * (0.18 + key + fill), vec3(1.0)), 1.0);
}`;

// The project renders' orange, as displayed: the shipped shaders write it as is, three.js's lit materials
// take it as sRGB (converted to linear for lighting and back on output).
const colour = new THREE.Color(0.93, 0.55, 0.25);
const colourSrgb = new THREE.Color().setRGB(0.93, 0.55, 0.25, THREE.SRGBColorSpace);

function shaderMaterial(vertexShader, uniforms) {
    return new THREE.RawShaderMaterial({
        glslVersion: THREE.GLSL3,
        vertexShader,
        fragmentShader,
        side: THREE.DoubleSide,
        uniforms: Object.assign({
            uModelViewProjection: { value: new THREE.Matrix4() },
            uNormalMatrix: { value: new THREE.Matrix3() },
            uColour: { value: new THREE.Vector3(colour.r, colour.g, colour.b) },
            uMatte: { value: matte },
        }, uniforms),
    });
}

// Feeds the shipped shaders' matrices from three.js's camera before each draw.
function followCamera(mesh) {
    mesh.frustumCulled = false;  // the rest bounds do not hold the motion
    mesh.onBeforeRender = (renderer, scene, camera) => {
        const modelView = new THREE.Matrix4().multiplyMatrices(camera.matrixWorldInverse, mesh.matrixWorld);
        mesh.material.uniforms.uModelViewProjection.value.multiplyMatrices(camera.projectionMatrix, modelView);
        mesh.material.uniforms.uNormalMatrix.value.getNormalMatrix(modelView);
    };
}

function frameBlend(time) {
    const f = Math.max(0, Math.min(clip.frames - 1, time * clip.fps));
    const a = Math.floor(f);
    return { a, b: Math.min(a + 1, clip.frames - 1), blend: f - a };
}

async function loadAnimatedGltf() {
    const gltf = await loadGltf(clip.main);
    gltf.scene.traverse((o) => {
        if (o.isMesh) {
            o.material = matte ? new THREE.MeshBasicMaterial({ color: 0xffffff, side: THREE.DoubleSide })
                               : new THREE.MeshStandardMaterial({ color: colourSrgb, roughness: 0.55, side: THREE.DoubleSide });
            o.frustumCulled = false;
        }
    });
    const mixer = new THREE.AnimationMixer(gltf.scene);
    const action = gltf.animations.length ? mixer.clipAction(gltf.animations[0]) : null;
    if (action) {
        action.setLoop(THREE.LoopOnce);  // the page loops and clamps the time itself
        action.clampWhenFinished = true;
        action.play();
    }
    // An action that reached its end once is paused by three.js (clampWhenFinished) and setTime alone does not
    // wake it: the clip stood on one frame while the label went on.
    const show = (time) => {
        if (action) {
            action.paused = false;
            action.enabled = true;
        }
        mixer.setTime(time);
    };
    return { root: gltf.scene, show };
}

async function loadVat() {
    const vat = clip.vat;
    const gltf = await loadGltf(vat.mesh);
    const exr = new EXRLoader();
    exr.setDataType(THREE.FloatType);
    const texture = (name) => {
        const image = exr.parse(fileBytes(name));
        // EXRLoader stores the last scanline first; the shipped shader wants scanline 0 as row t = 0.
        const row = image.width * 4, flipped = new Float32Array(image.data.length);
        for (let y = 0; y < image.height; ++y)
            flipped.set(image.data.subarray((image.height - 1 - y) * row, (image.height - y) * row), y * row);
        const t = new THREE.DataTexture(flipped, image.width, image.height, THREE.RGBAFormat, THREE.FloatType);
        t.minFilter = t.magFilter = THREE.NearestFilter;
        t.generateMipmaps = false;
        t.needsUpdate = true;
        return t;
    };
    const material = shaderMaterial(webglSource(clip.shaders.vat, []), {
        uOffsets: { value: texture(vat.positionTexture) },
        uNormals: { value: texture(vat.normalTexture) },
        uFrameRowStep: { value: vat.frameRowStep },
        uFrameA: { value: 0 }, uFrameB: { value: 0 }, uBlend: { value: 0 },
    });
    gltf.scene.traverse((o) => {
        if (!o.isMesh) return;
        o.geometry.setAttribute('inPosition', o.geometry.getAttribute('position'));
        o.geometry.setAttribute('inLookup', o.geometry.getAttribute('uv1'));
        o.material = material;
        followCamera(o);
    });
    return {
        root: gltf.scene,
        show: (time) => {
            const f = frameBlend(time);
            material.uniforms.uFrameA.value = f.a;
            material.uniforms.uFrameB.value = f.b;
            material.uniforms.uBlend.value = f.blend;
        },
    };
}

async function loadLattice() {
    const lattice = clip.lattice;
    const gltf = await loadGltf(lattice.mesh);
    // The .bin's nodes as they are, one RGB texel per node, frame after frame, in rows of `width`.
    const nodes = new Float32Array(fileBytes(lattice.nodesFile), lattice.nodeDataOffset, lattice.nodeCount * 3);
    const width = Math.min(lattice.nodeCount, 4096), height = Math.ceil(lattice.nodeCount / width);
    const texels = new Float32Array(width * height * 4);
    for (let i = 0; i < lattice.nodeCount; ++i) texels.set(nodes.subarray(3 * i, 3 * i + 3), 4 * i);
    const nodeTexture = new THREE.DataTexture(texels, width, height, THREE.RGBAFormat, THREE.FloatType);
    nodeTexture.minFilter = nodeTexture.magFilter = THREE.NearestFilter;
    nodeTexture.generateMipmaps = false;
    nodeTexture.needsUpdate = true;
    const source = webglSource(clip.shaders.lattice, ['LATTICE_NODE_TEXTURE']);
    const meshes = [];
    gltf.scene.traverse((o) => { if (o.isMesh) meshes.push(o); });
    const materials = lattice.objects.map((object) => {
        const mesh = meshes[object.primitive];
        if (!mesh) throw new Error('the mesh has no primitive ' + object.primitive);
        const material = shaderMaterial(source, {
            uLatticeNodeTexture: { value: nodeTexture },
            uNodeCount: { value: new THREE.Vector3(...object.nodes) },
            uDegree: { value: new THREE.Vector3(...object.degrees) },
            uNodesPerFrame: { value: lattice.nodesPerFrame },
            uFirstNode: { value: object.firstNode },
            uFrameA: { value: 0 }, uFrameB: { value: 0 }, uBlend: { value: 0 },
            uBoxAxes: { value: new THREE.Matrix3().fromArray(object.boxAxes) },
            uBoxSize: { value: new THREE.Vector3(...object.boxSize) },
        });
        mesh.geometry.setAttribute('inLatticeUvw', mesh.geometry.getAttribute('_lattice_uvw'));
        mesh.geometry.setAttribute('inNormal', mesh.geometry.getAttribute('normal'));
        mesh.material = material;
        followCamera(mesh);
        return material;
    });
    return {
        root: gltf.scene,
        show: (time) => {
            const f = frameBlend(time);
            for (const m of materials) {
                m.uniforms.uFrameA.value = f.a;
                m.uniforms.uFrameB.value = f.b;
                m.uniforms.uBlend.value = f.blend;
            }
        },
    };
}

async function main() {
    const renderer = new THREE.WebGLRenderer({ antialias: !stops, preserveDrawingBuffer: readback });
    renderer.setPixelRatio(stillFrames.length === 0 ? window.devicePixelRatio : 1);
    renderer.setSize(viewWidth(), viewHeight());
    document.getElementById('view').appendChild(renderer.domElement);

    const scene = new THREE.Scene();
    scene.background = new THREE.Color(matte ? 0x000000 : 0x5f6066);
    scene.add(new THREE.HemisphereLight(0xffffff, 0x404048, 1.2));
    const light = new THREE.DirectionalLight(0xfff8f0, 2.0);
    light.position.set(-0.5, 0.7, 0.6);

    const c = clip.camera;
    const camera = new THREE.PerspectiveCamera(c.fovYDegrees, viewWidth() / viewHeight(), c.near, c.far);
    camera.add(light);  // a headlight, as the project's renders light from the view
    scene.add(camera);
    const controls = new OrbitControls(camera, renderer.domElement);
    const resetView = () => {
        camera.position.fromArray(c.eye);
        camera.up.fromArray(c.up);
        controls.target.fromArray(c.centre);
        camera.lookAt(controls.target);
        controls.update();
    };
    resetView();

    const player = clip.kind === 'vat' ? await loadVat()
                 : clip.kind === 'lattice' ? await loadLattice()
                 : await loadAnimatedGltf();
    scene.add(player.root);

    const slider = document.getElementById('frame');
    const label = document.getElementById('label');
    const play = document.getElementById('play');
    slider.max = String(clip.frames - 1);
    // A glTF loop's closing key is frame 0 again at frames / fps: the cycle plays through it, one frame's time
    // from the last frame to the first. Other clips end on their last frame.
    const duration = clip.closesLoop ? clip.frames / clip.fps : Math.max(clip.frames - 1, 1) / clip.fps;
    let time = 0;  // frame= shows its frames below, then plays from the start if until= asks
    let playing = stillFrames.length === 0;
    const show = () => {
        player.show(time);
        const frame = Math.round(time * clip.fps) % clip.frames;
        slider.value = String(frame);
        label.textContent = 'frame ' + frame + ' of ' + clip.frames + ' · ' + clip.fps + ' fps · ' + clip.summary;
        play.textContent = playing ? 'Pause' : 'Play';
        renderer.render(scene, camera);
    };
    const setPlaying = (on) => { playing = on; show(); };
    const step = (frames) => { playing = false; time = Math.max(0, Math.min(duration, Math.round(time * clip.fps + frames) / clip.fps)); show(); };
    play.onclick = () => setPlaying(!playing);
    slider.oninput = () => { playing = false; time = Number(slider.value) / clip.fps; show(); };
    document.getElementById('reset').onclick = () => { resetView(); show(); };
    window.addEventListener('keydown', (e) => {
        if (e.key === ' ') { setPlaying(!playing); e.preventDefault(); }
        else if (e.key === 'ArrowLeft') step(-1);
        else if (e.key === 'ArrowRight') step(1);
        else if (e.key === 'Home') step(-clip.frames);
    });
    window.addEventListener('resize', () => {
        camera.aspect = viewWidth() / viewHeight();
        camera.updateProjectionMatrix();
        renderer.setSize(viewWidth(), viewHeight());
        show();
    });
    controls.addEventListener('change', () => { if (!playing) renderer.render(scene, camera); });

    // Stops: each picture shown is kept for readback with the label it was shown under.
    const pictures = [];
    const capture = () => {
        if (readback) pictures.push(label.textContent + '\t' + renderer.domElement.toDataURL('image/png'));
    };
    const finish = () => {
        if (readback) document.getElementById('readback').textContent = pictures.join('\n');
        document.title = 'ready';
    };
    for (const f of stillFrames) {
        time = f / clip.fps;
        show();
        capture();
    }
    if (stillFrames.length > 0 && playStops.length === 0) {
        finish();
        return;
    }
    if (stillFrames.length > 0) {
        time = 0;
        playing = true;
    }
    show();
    // One step of playback by dt seconds.
    let timer = 0;
    let elapsed = 0;  // seconds played, through any number of loops
    const advance = (dt) => {
        if (!playing) return;
        time += dt;
        elapsed += dt;
        if (time > duration) time = clip.loop ? time % duration : duration;
        if (playStops.length > 0 && elapsed >= playStops[0]) {
            // until=T: the frame the time has reached, drawn and handed over; playback goes on from the
            // unrounded time to the next stop, as if it had not stopped.
            playStops.shift();
            const played = time;
            time = Math.round(time * clip.fps) / clip.fps;
            playing = playStops.length > 0;
            show();
            capture();
            time = played;
            if (playing) return;
            renderer.setAnimationLoop(null);
            clearInterval(timer);
            finish();
            return;
        }
        show();
    };
    if (tick > 0) {
        // tick=S: S seconds a step, on a timer (a headless browser draws few animation frames but keeps its timers).
        timer = setInterval(() => advance(tick), 1000 * tick);
        return;
    }
    let last = performance.now();
    renderer.setAnimationLoop((now) => {
        // A frame's timestamp can come before the performance.now() read above: never a step backwards.
        const dt = Math.max(0, (now - last) / 1000);
        last = now;
        advance(dt);
    });
}

main().catch(fail);
