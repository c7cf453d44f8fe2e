// sgslam's viewer page: pulls frames and the map from the server over one
// WebSocket (viewer/src/server.h) and draws them with three.js.
import * as THREE from './three/three.module.js';
import { OrbitControls } from './three/OrbitControls.js';
import { parseMessage } from './protocol.js';

const MAP_INTERVAL_MS = 500;  // the map is asked for again this long after one is drawn
// Frames are asked for at most this often: 15 a second follow the camera smoothly,
// and a page that shares the CPU with the run (a laptop, a robot) takes less of it.
const FRAME_INTERVAL_MS = 66;
let lastFrameAsked = 0;
const LABEL_COLOURS = ['#3ddc84', '#ff4d4d', '#ffd23d'];  // kept, rejected, unjudged
const STATE_NAMES = { ok: 'tracking', lost: 'lost', not_initialized: 'initialising' };

// What the tests read (viewer/tests): counts of what arrived and was drawn.
const state = { info: null, frames: 0, maps: 0, frame: null, mapPoints: 0, cloudPoints: 0, pieces: 0,
                objects: 0, keyframes: 0, cells: 0, cellsVersion: 0, cellsDrawn: 0, truthPoints: 0, renders: 0, errors: [],
                drawnMaps: 0, paused: false, movers: 0, moverTrailPoints: 0 };
window.sgslamViewer = state;
// For the tests: the share of the 3-D view's pixels unlike the background, read in
// the same task as a drawing (the drawing buffer is not kept after it is shown).
state.litShare = () => {
  renderer.render(scene, camera);
  const gl = renderer.getContext(), w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
  const d = new Uint8Array(4 * w * h);
  gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, d);
  let n = 0;
  for (let i = 0; i < d.length; i += 4) {
    if (Math.abs(d[i] - 0x15) + Math.abs(d[i + 1] - 0x18) + Math.abs(d[i + 2] - 0x1c) > 30) n++;
  }
  return n / (w * h);
};

// ---- the 3-D view ----------------------------------------------------------
const container = document.getElementById('view3d');
// No antialiasing: on a machine without a GPU (software WebGL) it costs several
// times the drawing, and the page shares the CPU with the run it shows.
const renderer = new THREE.WebGLRenderer({ antialias: false });
renderer.setPixelRatio(window.devicePixelRatio);
container.appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0x15181c);
const camera = new THREE.PerspectiveCamera(60, 1, 0.01, 500);
camera.position.set(0, 2, 4);
const controls = new OrbitControls(camera, renderer.domElement);
controls.enableDamping = true;  // the view glides to a stop: drawn every animation frame meanwhile
// The SLAM world is the first camera's frame (x right, y down, z forward): turned
// half a turn about x, y is up and the camera looks along -z as in three.js.
const world = new THREE.Group();
world.rotation.x = Math.PI;
scene.add(world);
scene.add(new THREE.GridHelper(20, 40, 0x3a424b, 0x262c33));

const layers = {};
for (const name of ['path', 'truth', 'keyframes', 'points', 'cloud', 'cells', 'objects', 'movers', 'camera']) {
  layers[name] = new THREE.Group();
  world.add(layers[name]);
}

const pathLine = new THREE.Line(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ color: 0x4da3ff }));
layers.path.add(pathLine);
const truthLine = new THREE.Line(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ color: 0xff9f43 }));
layers.truth.add(truthLine);
let cells = null;  // the OctoMap's occupied cells, coloured by height
const keyframeLines = new THREE.LineSegments(new THREE.BufferGeometry(),
                                             new THREE.LineBasicMaterial({ color: 0x8e7dff }));
layers.keyframes.add(keyframeLines);
const mapPoints = new THREE.Points(new THREE.BufferGeometry(),
                                  new THREE.PointsMaterial({ color: 0xeeeeee, size: 2, sizeAttenuation: false }));
layers.points.add(mapPoints);
const cloudMaterial = new THREE.PointsMaterial({ size: 2, sizeAttenuation: false, vertexColors: true });
const pieces = new Map();  // keyframe id -> THREE.Points, placed by its keyframe's pose
// While the view is being turned the cloud is drawn in part, every COARSE_STRIDE-th
// point (each piece's points are stored in that order: a prefix is an even
// subsample): without a GPU, drawing 100 000 points takes 40 ms, a quarter of them 15.
const COARSE_STRIDE = 4;
let coarse = false;
function interleaved(array, itemSize, count) {
  const out = new array.constructor(array.length);
  let k = 0;
  for (let start = 0; start < COARSE_STRIDE; start++) {
    for (let i = start; i < count; i += COARSE_STRIDE, k++) {
      for (let c = 0; c < itemSize; c++) out[itemSize * k + c] = array[itemSize * i + c];
    }
  }
  return out;
}
function setDrawRange(p) {
  const n = p.geometry.attributes.position.count;
  p.geometry.setDrawRange(0, coarse ? Math.ceil(n / COARSE_STRIDE) : n);
}

// A camera drawn as a pyramid: its centre and the image's corners at depth d.
function frustumSegments(d) {
  const w = 0.66 * d, h = 0.5 * d;
  const c = [[-w, -h, d], [w, -h, d], [w, h, d], [-w, h, d]];
  const s = [];
  for (let i = 0; i < 4; i++) s.push([0, 0, 0], c[i], c[i], c[(i + 1) % 4]);
  return s.flat();
}
const FRUSTUM = frustumSegments(0.08);
const currentCamera = new THREE.LineSegments(
  new THREE.BufferGeometry().setAttribute('position', new THREE.Float32BufferAttribute(frustumSegments(0.15), 3)),
  new THREE.LineBasicMaterial({ color: 0x3ddc84 }));
currentCamera.matrixAutoUpdate = false;
currentCamera.visible = false;
layers.camera.add(currentCamera);

function resize() {
  const w = container.clientWidth, h = container.clientHeight;
  renderer.setSize(w, h, false);
  renderer.domElement.style.width = w + 'px';
  renderer.domElement.style.height = h + 'px';
  camera.aspect = w / Math.max(h, 1);
  camera.updateProjectionMatrix();
}
window.addEventListener('resize', () => { resize(); requestRender(); });
resize();

// Drawn on demand: when something arrived or the view moved. What arrives is drawn
// at most every RENDER_INTERVAL_MS (without a GPU a drawing costs the machine tens
// of milliseconds, and the run shares it); a view the mouse turns, every frame.
let dirty = true, lastRender = 0;
const RENDER_INTERVAL_MS = 200;
function requestRender() { dirty = true; }
controls.addEventListener('change', requestRender);
let interacting = false, settling = false;  // from the mouse's 'start' until the glide stops
controls.addEventListener('start', () => {
  interacting = coarse = true;
  settling = false;
  for (const p of pieces.values()) setDrawRange(p);
});
controls.addEventListener('end', () => { settling = true; });
function animate() {
  requestAnimationFrame(animate);
  const moved = controls.update();
  if (moved) dirty = true;
  if (!moved && settling) {
    settling = interacting = coarse = false;
    for (const p of pieces.values()) setDrawRange(p);
    dirty = true;
  }
  if (!dirty) return;
  if (!interacting && performance.now() - lastRender < RENDER_INTERVAL_MS) return;
  lastRender = performance.now();
  dirty = false;
  renderer.render(scene, camera);
  state.drawnMaps = state.maps;  // the maps received by the time of this drawing
  state.renders++;
}
requestAnimationFrame(animate);

// ---- following the camera, top view, layers ----------------------------------
const follow = document.getElementById('c-follow');
const cameraWorld = new THREE.Vector3();
function followCamera() {
  if (!follow.checked || !currentCamera.visible) return;
  currentCamera.getWorldPosition(cameraWorld);
  const offset = camera.position.clone().sub(controls.target);
  controls.target.copy(cameraWorld);
  camera.position.copy(cameraWorld).add(offset);
}
document.getElementById('b-top').addEventListener('click', () => {
  const distance = Math.max(camera.position.distanceTo(controls.target), 3);
  camera.position.set(controls.target.x, controls.target.y + distance, controls.target.z + 0.001);
  camera.lookAt(controls.target);
  requestRender();
});
for (const box of document.querySelectorAll('#layers input')) {
  layers[box.dataset.layer].visible = box.checked;
  box.addEventListener('change', () => {
    layers[box.dataset.layer].visible = box.checked;
    requestRender();
  });
}

// ---- the current frame ---------------------------------------------------------
const imageCanvas = document.getElementById('image');
const ctx = imageCanvas.getContext('2d');

async function drawFrame(header, buffers) {
  if (buffers.image && buffers.image.length > 0) {
    const bitmap = await createImageBitmap(new Blob([buffers.image], { type: 'image/jpeg' }));
    if (imageCanvas.width !== bitmap.width) imageCanvas.width = bitmap.width;
    if (imageCanvas.height !== bitmap.height) imageCanvas.height = bitmap.height;
    ctx.drawImage(bitmap, 0, 0);
    bitmap.close();
  }
  const xy = buffers.keypoints, labels = buffers.labels;
  for (let i = 0; xy && i < labels.length; i++) {
    ctx.strokeStyle = LABEL_COLOURS[labels[i]] || '#ffffff';
    ctx.strokeRect(xy[2 * i] - 2, xy[2 * i + 1] - 2, 4, 4);
  }
  ctx.font = '13px system-ui, sans-serif';
  ctx.lineWidth = 2;
  for (const d of header.detections) {
    const [x, y, w, h] = d.box;
    ctx.strokeStyle = d.carried ? '#ff9f43' : '#4da3ff';
    ctx.strokeRect(x, y, w, h);
    const text = `${d.name} ${d.score.toFixed(2)}${d.carried ? ' (carried)' : ''}`;
    ctx.fillStyle = 'rgba(0,0,0,0.6)';
    ctx.fillRect(x, Math.max(y - 16, 0), ctx.measureText(text).width + 6, 16);
    ctx.fillStyle = '#ffffff';
    ctx.fillText(text, x + 3, Math.max(y - 4, 12));
  }
  ctx.lineWidth = 1;
}

function setText(id, text) { document.getElementById(id).textContent = text; }

function showFrame(header, buffers) {
  state.frames++;
  requestRender();
  state.frame = header;
  if (header.pose) {
    currentCamera.matrix.fromArray(header.pose);
    currentCamera.visible = true;
    followCamera();
  }
  setText('p-frame', `${header.index + 1}${state.info && state.info.frames ? ' of ' + state.info.frames : ''}`);
  const stateName = STATE_NAMES[header.state] || header.state;
  setText('p-state', stateName + (header.keyframe ? ' (keyframe)' : '') + (header.paused ? ', paused' : ''));
  showPaused(header.paused);
  setText('p-ms', `${header.frame_ms.toFixed(1)} ms`);
  setText('p-fps', header.fps.toFixed(1));
  setText('p-rejected', `${(100 * header.rejected_share).toFixed(1)} %`);
  setText('p-keyframes', header.keyframes);
  setText('p-points', header.map_points);
  showLiveMovers(header.t, header.movers);
  return drawFrame(header, buffers);
}

// ---- the map ------------------------------------------------------------------------
function setPositions(geometry, array) {
  geometry.setAttribute('position', new THREE.BufferAttribute(array, 3));
  geometry.computeBoundingSphere();
}

const objectBoxes = new THREE.Group();
layers.objects.add(objectBoxes);
// A text on a dark ground, 0.075 high, as wide as the text.
function label(text, colour = '#ffd23d') {
  const c = document.createElement('canvas');
  const font = '28px system-ui, sans-serif';
  const g = c.getContext('2d');
  g.font = font;
  c.width = Math.ceil(g.measureText(text).width) + 16; c.height = 48;
  g.fillStyle = 'rgba(0,0,0,0.6)';
  g.fillRect(0, 0, c.width, 48);
  g.font = font;  // the canvas's state went with its resizing
  g.fillStyle = colour;
  g.fillText(text, 8, 34);
  const sprite = new THREE.Sprite(new THREE.SpriteMaterial({ map: new THREE.CanvasTexture(c), depthTest: false }));
  sprite.scale.set((0.075 * c.width) / 48, 0.075, 1);
  sprite.rotation.x = Math.PI;  // the world group's turn would show it upside down
  return sprite;
}
let objectsShown = '';
function showObjects(objects) {
  const text = JSON.stringify(objects);
  if (text === objectsShown) return;  // unchanged: no new labels to draw and upload
  objectsShown = text;
  for (const child of [...objectBoxes.children]) {
    objectBoxes.remove(child);
    child.traverse((o) => { o.geometry?.dispose(); o.material?.map?.dispose(); o.material?.dispose(); });
  }
  for (const o of objects) {
    const box = new THREE.LineSegments(new THREE.EdgesGeometry(new THREE.BoxGeometry(...o.size)),
                                       new THREE.LineBasicMaterial({ color: 0xffd23d }));
    box.position.set(...o.centroid);
    objectBoxes.add(box);
    // The class the views voted for, its share of the votes and the views (docs/object-map.md).
    const l = label(`${o.class} ${Math.round(100 * (o.class_share ?? 1))}% · ${o.observations} views`);
    l.position.set(o.centroid[0], o.centroid[1] - o.size[1] / 2 - 0.08, o.centroid[2]);
    objectBoxes.add(l);
  }
  state.objects = objects.length;
  setText('p-objects', objects.length);
}

function showCells(c) {
  if (cells) {
    layers.cells.remove(cells);
    cells.geometry.dispose();
    cells.material.dispose();
    cells = null;
  }
  const n = c.length / 4;
  state.cells = n;
  if (n === 0) return;
  // Each cell a square of its side facing the view (points, not cubes: 50 000
  // cubes are 600 000 triangles, too many to draw without a GPU).
  let low = Infinity, high = -Infinity;
  for (let i = 0; i < n; i++) { low = Math.min(low, c[4 * i + 1]); high = Math.max(high, c[4 * i + 1]); }
  const xyz = new Float32Array(3 * n), rgb = new Float32Array(3 * n), colour = new THREE.Color();
  for (let i = 0; i < n; i++) {
    xyz[3 * i] = c[4 * i]; xyz[3 * i + 1] = c[4 * i + 1]; xyz[3 * i + 2] = c[4 * i + 2];
    // y points down in the world: the highest cells (least y) are red, the lowest blue.
    colour.setHSL((0.66 * (c[4 * i + 1] - low)) / Math.max(high - low, 1e-6), 0.8, 0.5);
    rgb[3 * i] = colour.r; rgb[3 * i + 1] = colour.g; rgb[3 * i + 2] = colour.b;
  }
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(xyz, 3));
  g.setAttribute('color', new THREE.BufferAttribute(rgb, 3));
  g.computeBoundingSphere();
  cells = new THREE.Points(g, new THREE.PointsMaterial({ size: c[3], sizeAttenuation: true, vertexColors: true }));
  layers.cells.add(cells);
}

// ---- the movers ------------------------------------------------------------------
// The mover tracks (movers/mover_tracker.h): a confirmed or lost one is a box of its
// extent at its centroid, labelled with its id and class, and its path over the last
// MOVER_TRAIL_S, in a colour of its id; a lost one (coasting on its last velocity)
// dashed and dimmer. Tentative ones are not drawn: most are noise that never
// confirms, and their paths are left out too. A live run's tracks come with each
// frame and the page keeps their paths; a finished run's (tracks.txt) with its map,
// shown at the frame its slider picks.
const MOVER_TRAIL_S = 3;
const MOVER_TRAIL_MAX = 512;  // points of a path at most (3 s at 30 Hz are 90)
const MOVER_STATES = ['tentative', 'confirmed', 'lost'];  // a finished run's state codes (viewer/src/movers.h)
const unitBox = new THREE.EdgesGeometry(new THREE.BoxGeometry(1, 1, 1));
new THREE.LineSegments(unitBox).computeLineDistances();  // the dashes' distances, on the geometry every box shares
const moverGroup = new THREE.Group();
layers.movers.add(moverGroup);
const moverViews = new Map();  // track id -> its box, label and path

function moverView(id) {
  let v = moverViews.get(id);
  if (v) return v;
  const colour = new THREE.Color().setHSL((id * 0.618034) % 1, 0.85, 0.6);  // the golden angle: neighbours differ
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3 * MOVER_TRAIL_MAX), 3));
  const trail = new THREE.Line(g, new THREE.LineBasicMaterial({ color: colour }));
  trail.frustumCulled = false;  // its bounds change with every frame: not worth computing
  v = { solid: new THREE.LineBasicMaterial({ color: colour }),
        dashed: new THREE.LineDashedMaterial({ color: colour, dashSize: 0.06, gapSize: 0.06, transparent: true,
                                               opacity: 0.5 }),
        trail, label: null, text: '', css: `#${colour.getHexString()}` };
  v.box = new THREE.LineSegments(unitBox, v.solid);
  moverGroup.add(v.box, trail);
  moverViews.set(id, v);
  return v;
}

function dropLabel(v) {
  if (!v.label) return;
  moverGroup.remove(v.label);
  v.label.material.map.dispose();
  v.label.material.dispose();
  v.label = null;
}

// movers: [{ id, class, state, position, extent }]; trails: id -> its path's
// positions (x, y, z each), oldest first. A track that ended goes with its path.
function drawMovers(movers, trails) {
  const shown = new Map();
  for (const m of movers) if (m.state !== 'tentative') shown.set(m.id, m);
  for (const id of shown.keys()) moverView(id);
  let trailPoints = 0, lost = 0;
  for (const [id, v] of moverViews) {
    const m = shown.get(id), xyz = trails.get(id) || [];
    if (!m) {
      dropLabel(v);
      moverGroup.remove(v.box, v.trail);
      v.trail.geometry.dispose();
      v.trail.material.dispose();
      v.solid.dispose();
      v.dashed.dispose();
      moverViews.delete(id);
      continue;
    }
    const isLost = m.state === 'lost';
    lost += isLost;
    v.box.position.set(...m.position);
    v.box.scale.set(...m.extent.map((e) => Math.max(e, 0.02)));  // a flat box's matrix would not invert
    v.box.material = isLost ? v.dashed : v.solid;
    const text = `${id} ${m.class}`;
    if (text !== v.text) {
      dropLabel(v);
      v.label = label(text, v.css);
      // Of one size on the screen: a mover is often seen from afar, among others.
      v.label.material.sizeAttenuation = false;
      v.label.scale.multiplyScalar(0.4);
      v.text = text;
      moverGroup.add(v.label);
    }
    v.label.position.set(m.position[0], m.position[1] - m.extent[1] / 2 - 0.08, m.position[2]);
    v.label.material.opacity = isLost ? 0.5 : 1;
    const n = Math.min(xyz.length / 3, MOVER_TRAIL_MAX);
    const position = v.trail.geometry.attributes.position;
    for (let i = 0, from = xyz.length - 3 * n; i < 3 * n; i++) position.array[i] = xyz[from + i];
    position.needsUpdate = true;
    v.trail.geometry.setDrawRange(0, n);
    trailPoints += n;
  }
  state.movers = shown.size;
  state.moverTrailPoints = trailPoints;
  setText('p-movers', `${shown.size - lost} confirmed, ${lost} lost`);
}

// A live run: each path is the positions of its track in the frames the page got.
const livePaths = new Map();  // id -> { t: [s], xyz: [m] }
function showLiveMovers(t, movers) {
  for (const m of movers) {
    if (m.state === 'tentative') continue;
    if (!livePaths.has(m.id)) livePaths.set(m.id, { t: [], xyz: [] });
    const p = livePaths.get(m.id);
    p.t.push(t);
    p.xyz.push(...m.position);
  }
  const trails = new Map();
  for (const [id, p] of livePaths) {
    let old = 0;
    while (old < p.t.length && p.t[old] < t - MOVER_TRAIL_S) old++;
    p.t.splice(0, old);
    p.xyz.splice(0, 3 * old);
    if (p.t.length === 0) livePaths.delete(id);
    else trails.set(id, p.xyz);
  }
  drawMovers(movers, trails);
}

// A finished run: its tracks' lines (viewer/src/movers.h: by frame), shown at the
// slider's frame with their paths up to it.
const replayBox = document.getElementById('replay');
const replaySlider = document.getElementById('c-replay');
let replay = null;
function setUpReplay(message, classes) {
  // Copies: views would keep the whole message, cloud and all, for as long as the page.
  const b = {};
  for (const name of ['path_t', 'mover_frame', 'mover_id', 'mover_class', 'mover_state', 'mover_position',
                      'mover_extent']) {
    b[name] = message[name].slice();
  }
  const n = b.mover_id.length, frames = b.path_t.length;
  const frameStart = new Uint32Array(frames + 1), byId = new Map(), rank = new Uint32Array(n);
  let last = 0;  // the last frame with a confirmed track: where the slider starts
  for (let i = 0; i < n; i++) {
    frameStart[b.mover_frame[i] + 1]++;
    if (!byId.has(b.mover_id[i])) byId.set(b.mover_id[i], []);
    const lines = byId.get(b.mover_id[i]);
    rank[i] = lines.length;
    lines.push(i);
    if (MOVER_STATES[b.mover_state[i]] === 'confirmed') last = b.mover_frame[i];
  }
  for (let f = 0; f < frames; f++) frameStart[f + 1] += frameStart[f];
  replay = { b, classes, frameStart, byId, rank };
  replaySlider.max = frames - 1;
  replaySlider.value = last;
  replayBox.hidden = false;
  showReplayFrame(last);
}
function showReplayFrame(k) {
  const { b, classes, frameStart, byId, rank } = replay;
  const t = b.path_t[k], movers = [], trails = new Map();
  for (let i = frameStart[k]; i < frameStart[k + 1]; i++) {
    const m = { id: b.mover_id[i], class: classes[b.mover_class[i]], state: MOVER_STATES[b.mover_state[i]],
                position: Array.from(b.mover_position.subarray(3 * i, 3 * i + 3)),
                extent: Array.from(b.mover_extent.subarray(3 * i, 3 * i + 3)) };
    movers.push(m);
    if (m.state === 'tentative') continue;
    const lines = byId.get(m.id), path = [];
    for (let j = rank[i]; j >= 0 && b.path_t[b.mover_frame[lines[j]]] >= t - MOVER_TRAIL_S; j--) {
      if (MOVER_STATES[b.mover_state[lines[j]]] !== 'tentative') path.push(lines[j]);
    }
    const xyz = [];
    for (let j = path.length - 1; j >= 0; j--) xyz.push(...b.mover_position.subarray(3 * path[j], 3 * path[j] + 3));
    trails.set(m.id, xyz);
  }
  drawMovers(movers, trails);
  setText('p-replay', `frame ${k + 1} of ${b.path_t.length}, ${t.toFixed(1)} s`);
  requestRender();
}
replaySlider.addEventListener('input', () => showReplayFrame(Number(replaySlider.value)));

// The first map of a finished run: the view is moved to see all of it, from above
// and behind the first camera.
function fitView(points) {
  const box = new THREE.Box3().setFromBufferAttribute(new THREE.BufferAttribute(points, 3));
  if (box.isEmpty()) return;
  box.applyMatrix4(world.matrixWorld);
  const sphere = box.getBoundingSphere(new THREE.Sphere());
  controls.target.copy(sphere.center);
  camera.position.copy(sphere.center).add(new THREE.Vector3(0, 0.8, 1.2).multiplyScalar(1.6 * sphere.radius));
  camera.lookAt(sphere.center);
}

function showMap(header, b) {
  state.maps++;
  requestRender();
  showPaused(header.paused);
  if (header.cells_version !== undefined) state.cellsVersion = header.cells_version;
  if (state.maps === 1 && state.info && !state.info.live) {
    world.updateMatrixWorld();
    fitView(b.points.length > 0 ? b.points : b.path);
  }
  if (b.truth) {
    setPositions(truthLine.geometry, b.truth);
    state.truthPoints = b.truth.length / 3;
  }
  if (b.cells) {
    showCells(b.cells);
    state.cellsDrawn = state.cellsVersion;
  }
  setPositions(mapPoints.geometry, b.points);
  state.mapPoints = b.points.length / 3;
  setPositions(pathLine.geometry, b.path);
  // Keyframes: a small pyramid each, placed by its pose.
  const n = b.keyframe_ids.length, segs = new Float32Array(n * FRUSTUM.length);
  const m = new THREE.Matrix4(), v = new THREE.Vector3();
  for (let k = 0; k < n; k++) {
    m.fromArray(b.keyframe_poses, 16 * k);
    for (let i = 0; i < FRUSTUM.length; i += 3) {
      v.set(FRUSTUM[i], FRUSTUM[i + 1], FRUSTUM[i + 2]).applyMatrix4(m);
      segs.set([v.x, v.y, v.z], k * FRUSTUM.length + i);
    }
  }
  setPositions(keyframeLines.geometry, segs);
  state.keyframes = n;
  // The cloud: new pieces, every piece moved to its keyframe's pose, gone ones dropped.
  let offset = 0;
  for (let i = 0; i < b.new_piece_ids.length; i++) {
    const count = b.new_piece_counts[i];
    const g = new THREE.BufferGeometry();
    const xyz = b.new_piece_xyz.subarray(3 * offset, 3 * (offset + count));
    const rgb = b.new_piece_rgb.subarray(3 * offset, 3 * (offset + count));
    g.setAttribute('position', new THREE.BufferAttribute(interleaved(xyz, 3, count), 3));
    g.setAttribute('color', new THREE.BufferAttribute(interleaved(rgb, 3, count), 3, true));
    g.computeBoundingSphere();
    const p = new THREE.Points(g, cloudMaterial);
    setDrawRange(p);
    p.matrixAutoUpdate = false;
    pieces.set(b.new_piece_ids[i], p);
    layers.cloud.add(p);
    offset += count;
  }
  const present = new Set();
  for (let i = 0; i < b.piece_ids.length; i++) {
    const p = pieces.get(b.piece_ids[i]);
    present.add(b.piece_ids[i]);
    if (p) p.matrix.fromArray(b.piece_poses, 16 * i);
  }
  let cloudPoints = 0;
  for (const [id, p] of pieces) {
    if (!present.has(id)) {
      layers.cloud.remove(p);
      p.geometry.dispose();
      pieces.delete(id);
    } else {
      cloudPoints += p.geometry.attributes.position.count;
    }
  }
  state.pieces = pieces.size;
  state.cloudPoints = cloudPoints;
  showObjects(header.objects);
  if (b.mover_id && b.mover_id.length > 0 && !replay) setUpReplay(b, header.mover_classes);
  else if (b.mover_id && !replay) setText('p-movers', 'none in tracks.txt');
  if (state.info && !state.info.live) {
    setText('p-keyframes', n);
    setText('p-points', state.mapPoints);
  }
}

// ---- the connection -------------------------------------------------------------------
const status = document.getElementById('status');
const pauseButton = document.getElementById('b-pause');
const stepButton = document.getElementById('b-step');
let socket = null;
// The run is paused while any page holds a pause (viewer/src/pause.h): the button
// shows the server's state, which frames, maps and the answer to a control bring.
// Between a control and its answer, what comes may have been made before it.
let unanswered = 0;  // controls sent whose answering info has not come
function showPaused(paused) {
  if (paused === undefined || unanswered > 0) return;
  pauseButton.textContent = paused ? 'resume' : 'pause';
  state.paused = paused;
}
function sendControl(what) {
  send({ control: what });
  send({ get: 'info' });  // answered after the control: the state it left
  unanswered++;
}

function send(message) {
  if (socket && socket.readyState === WebSocket.OPEN) socket.send(JSON.stringify(message));
}
function requestMap() {
  // The OctoMap's cells (up to a megabyte, and costly to build) only while shown.
  const cellsHave = layers.cells.visible ? state.cellsDrawn : state.cellsVersion;
  send({ get: 'map', pieces_after: maxPieceId(), cells_have: cellsHave });
}
function maxPieceId() {
  let max = -1;
  for (const id of pieces.keys()) max = Math.max(max, id);
  return max;
}

pauseButton.addEventListener('click', () => {
  const paused = pauseButton.textContent === 'resume';
  sendControl(paused ? 'resume' : 'pause');
  pauseButton.textContent = paused ? 'pause' : 'resume';
});
stepButton.addEventListener('click', () => {
  sendControl('step');
  pauseButton.textContent = 'resume';
});

function connect() {
  socket = new WebSocket(`ws://${location.host}/ws`);
  socket.binaryType = 'arraybuffer';
  socket.onopen = () => {
    status.textContent = '';
    unanswered = 0;  // a new connection holds no pause; its info says whether another page does
    send({ get: 'info' });
    send({ get: 'frame', have: 0 });
    requestMap();
  };
  socket.onmessage = async (event) => {
    try {
      const { header, buffers } = parseMessage(event.data);
      if (header.type === 'info') {
        unanswered = Math.max(unanswered - 1, 0);
        showPaused(header.paused);
        state.info = header;
        setText('p-run', `${header.live ? 'live' : 'finished run'}: ${header.dataset} (${header.mode})`);
        document.title = `sgslam viewer: ${header.dataset}`;
        pauseButton.disabled = stepButton.disabled = !header.pausable;
        if (!header.live) {
          imageCanvas.style.display = 'none';
          setText('p-frame', `${header.frames} frames`);
          setText('p-state', 'finished');
        }
      } else if (header.type === 'frame') {
        await showFrame(header, buffers);
        const wait = Math.max(0, lastFrameAsked + FRAME_INTERVAL_MS - performance.now());
        setTimeout(() => {
          lastFrameAsked = performance.now();
          send({ get: 'frame', have: header.version });
        }, wait);
      } else if (header.type === 'map') {
        showMap(header, buffers);
        // A finished run's map does not change: asked for once.
        if (state.info && state.info.live) setTimeout(requestMap, MAP_INTERVAL_MS);
      }
    } catch (e) {
      state.errors.push(String(e));
      status.textContent = `error: ${e}`;
    }
  };
  socket.onclose = () => {
    status.textContent = 'disconnected (the run has ended or the server stopped); retrying…';
    setTimeout(connect, 2000);
  };
}
connect();
