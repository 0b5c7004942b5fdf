// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// cellguard-monitor's browser view: the grid, zones, prior, live foreground
// and unseen zone parts in 3D (three.js r111 from libjs-three, served by the
// monitor), the zone table from Server-Sent Events (/api/events, 10 Hz) and
// the stop history. Read-only: it only GETs.
import * as THREE from '/three/build/three.module.js';
import { OrbitControls } from '/three/examples/jsm/controls/OrbitControls.js';

const STATE_COLOURS = { CLEAR: 0x2e7d32, INTRUDED: 0xe53935, UNSEEN: 0xffd600, FAULT: 0x8e24aa, INACTIVE: 0x757575 };
const STALE_MS = 1000;  // no event for this long: the view says STALE, not live
const MAX_POINTS = 4096;

const MAX_KEPT = 16;  // distinct zone-state sets whose first message the view keeps (for replay)
const view = { k: -1, cycle: 0, states: [], events: 0, lastEventAt: 0, history: {}, kept: {}, staticLoaded: false,
  error: '' };
window.cgView = view;  // read by the headless-browser test

let grid = null;
let zoneMeshes = [];
let fgPoints = null;
let unseenPoints = null;
let scene3d = null;
const capsules = [];  // pool: one group (cylinder + two spheres) per robot capsule, hidden when unused

// r111 has no CapsuleGeometry: a unit cylinder along y and two unit spheres, scaled per capsule.
const CYLINDER = new THREE.CylinderBufferGeometry(1, 1, 1, 16, 1, true);
const SPHERE = new THREE.SphereBufferGeometry(1, 16, 12);
const CAPSULE_MATERIAL = new THREE.MeshLambertMaterial({ color: 0x42a5f5, transparent: true, opacity: 0.8 });
const Y_AXIS = new THREE.Vector3(0, 1, 0);

function capsule(i) {
  while (capsules.length <= i) {
    const g = new THREE.Group();
    g.add(new THREE.Mesh(CYLINDER, CAPSULE_MATERIAL));
    g.add(new THREE.Mesh(SPHERE, CAPSULE_MATERIAL));
    g.add(new THREE.Mesh(SPHERE, CAPSULE_MATERIAL));
    scene3d.add(g);
    capsules.push(g);
  }
  return capsules[i];
}

function setCapsules(list) {
  if (!scene3d) return;
  list.forEach((c, i) => {
    const a = new THREE.Vector3(c[0], c[1], c[2]);
    const b = new THREE.Vector3(c[3], c[4], c[5]);
    const r = c[6];
    const g = capsule(i);
    const [cyl, sa, sb] = g.children;
    const axis = new THREE.Vector3().subVectors(b, a);
    const len = axis.length();
    cyl.position.copy(a).add(b).multiplyScalar(0.5);
    cyl.quaternion.setFromUnitVectors(Y_AXIS, len > 1e-9 ? axis.clone().normalize() : Y_AXIS);
    cyl.scale.set(r, Math.max(len, 1e-6), r);
    sa.position.copy(a);
    sb.position.copy(b);
    sa.scale.setScalar(r);
    sb.scale.setScalar(r);
    g.visible = true;
  });
  for (let i = list.length; i < capsules.length; ++i) capsules[i].visible = false;
}

function voxelCentre(i, out, o) {
  const [nx, ny] = grid.dims;
  const x = i % nx;
  const y = Math.floor(i / nx) % ny;
  const z = Math.floor(i / (nx * ny));
  out[o] = grid.origin[0] + (x + 0.5) * grid.voxel_size;
  out[o + 1] = grid.origin[1] + (y + 0.5) * grid.voxel_size;
  out[o + 2] = grid.origin[2] + (z + 0.5) * grid.voxel_size;
}

function pointsOf(indices, colour, size, capacity) {
  const positions = new Float32Array(Math.max(capacity, 1) * 3);
  indices.forEach((v, n) => voxelCentre(v, positions, n * 3));
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  geometry.setDrawRange(0, indices.length);
  return new THREE.Points(geometry, new THREE.PointsMaterial({ color: colour, size: size }));
}

function setPoints(points, indices) {
  const attr = points.geometry.getAttribute('position');
  const n = Math.min(indices.length, MAX_POINTS);
  for (let i = 0; i < n; ++i) voxelCentre(indices[i], attr.array, i * 3);
  attr.needsUpdate = true;
  points.geometry.setDrawRange(0, n);
  points.geometry.computeBoundingSphere();
}

function zoneGeometry(z) {
  if (z.shape === 'box') {
    const g = new THREE.BoxBufferGeometry(z.max[0] - z.min[0], z.max[1] - z.min[1], z.max[2] - z.min[2]);
    g.translate((z.min[0] + z.max[0]) / 2, (z.min[1] + z.max[1]) / 2, (z.min[2] + z.max[2]) / 2);
    return g;
  }
  const shape = new THREE.Shape(z.polygon.map(p => new THREE.Vector2(p[0], p[1])));
  const g = new THREE.ExtrudeBufferGeometry(shape, { depth: z.z_max - z.z_min, bevelEnabled: false });
  g.translate(0, 0, z.z_min);
  return g;
}

function buildScene(s) {
  const holder = document.getElementById('canvas-holder');
  let renderer;
  try {
    renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  } catch (e) {  // no WebGL: say so where the 3D view would be; the rest of the page is live
    view.webgl = false;
    document.getElementById('no-webgl').hidden = false;
    return;
  }
  view.webgl = true;
  renderer.setPixelRatio(window.devicePixelRatio);
  holder.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  scene3d = scene;
  scene.add(new THREE.AmbientLight(0xffffff, 0.6));
  const sun = new THREE.DirectionalLight(0xffffff, 0.6);
  sun.position.set(2, -3, 5);
  scene.add(sun);
  scene.background = new THREE.Color(0x15181c);
  const size = [s.dims[0] * s.voxel_size, s.dims[1] * s.voxel_size, s.dims[2] * s.voxel_size];
  const centre = new THREE.Vector3(s.origin[0] + size[0] / 2, s.origin[1] + size[1] / 2, s.origin[2] + size[2] / 3);
  const camera = new THREE.PerspectiveCamera(45, 1, 0.05, 100);
  camera.up.set(0, 0, 1);
  const reach = Math.max(size[0], size[1], size[2]);
  camera.position.set(centre.x - 0.9 * reach, centre.y - 1.3 * reach, centre.z + 1.1 * reach);
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.target.copy(centre);
  controls.update();
  // The grid's bounds and floor.
  const bounds = new THREE.BoxBufferGeometry(size[0], size[1], size[2]);
  bounds.translate(s.origin[0] + size[0] / 2, s.origin[1] + size[1] / 2, s.origin[2] + size[2] / 2);
  scene.add(new THREE.LineSegments(new THREE.EdgesGeometry(bounds), new THREE.LineBasicMaterial({ color: 0x607d8b })));
  // The prior: background surfaces as grey points, the removed interiors darker.
  scene.add(pointsOf(s.background, 0x9e9e9e, s.voxel_size * 0.5, s.background.length));
  scene.add(pointsOf(s.interior, 0x4e4e4e, s.voxel_size * 0.35, s.interior.length));
  // The zones: translucent, coloured by state; outlined in their kind's colour.
  zoneMeshes = s.zones.map(z => {
    const g = zoneGeometry(z);
    const mesh = new THREE.Mesh(g, new THREE.MeshBasicMaterial({ color: STATE_COLOURS.INACTIVE, transparent: true,
      opacity: 0.22, depthWrite: false }));
    scene.add(mesh);
    scene.add(new THREE.LineSegments(new THREE.EdgesGeometry(g),
      new THREE.LineBasicMaterial({ color: z.kind === 'protective' ? 0xe53935 : 0xfdd835 })));
    return mesh;
  });
  fgPoints = pointsOf([], 0xff1744, s.voxel_size * 0.9, MAX_POINTS);
  unseenPoints = pointsOf([], 0xffea00, s.voxel_size * 0.6, MAX_POINTS);
  scene.add(fgPoints);
  scene.add(unseenPoints);
  const resize = () => {
    const w = holder.clientWidth;
    const h = holder.clientHeight;
    renderer.setSize(w, h);
    camera.aspect = w / Math.max(h, 1);
    camera.updateProjectionMatrix();
  };
  window.addEventListener('resize', resize);
  resize();
  const animate = () => { requestAnimationFrame(animate); renderer.render(scene, camera); };
  animate();
}

function buildTable(s) {
  const body = document.querySelector('#zones tbody');
  s.zones.forEach((z, i) => {
    const tr = document.createElement('tr');
    tr.innerHTML = `<td></td><td>${z.kind}</td><td id="zone-state-${i}">-</td>` +
      `<td id="zone-fg-${i}">-</td><td id="zone-unseen-${i}">-</td>`;
    tr.firstChild.textContent = z.name;
    body.appendChild(tr);
  });
}

// Draws one cycle's message. A replayed one (a kept message drawn again once the stream has
// ended) changes neither the liveness nor the history: the page still says STALE.
function showState(st, replayed = false) {
  view.k = st.k;
  view.cycle = st.cycle;
  view.states = st.zones.map(z => z.state);
  if (!replayed) {
    view.events += 1;
    view.lastEventAt = performance.now();
    view.lastAgeMs = st.age_ms;
    view.history[st.k] = view.states;
    const key = view.states.join(',');
    if (!(key in view.kept) && Object.keys(view.kept).length < MAX_KEPT) view.kept[key] = st;
  }
  document.getElementById('cycle').textContent = st.cycle;
  document.getElementById('k').textContent = st.k;
  const flag = (id, on, text) => {
    const e = document.getElementById(id);
    e.textContent = text;
    e.className = 'flag ' + (on ? 'on' : 'off');
  };
  flag('stop', st.stop, st.stop ? 'STOP' : 'run');
  flag('warning', st.warning, st.warning ? 'WARNING' : 'no warning');
  document.getElementById('faults').textContent = st.latched_faults === 0 ? '-' :
    '0x' + st.latched_faults.toString(16);
  st.zones.forEach((z, i) => {
    const cell = document.getElementById(`zone-state-${i}`);
    if (cell) {
      cell.textContent = z.state;
      cell.className = 'state-' + z.state;
      document.getElementById(`zone-fg-${i}`).textContent = z.foreground;
      document.getElementById(`zone-unseen-${i}`).textContent = z.unseen;
    }
    if (zoneMeshes[i]) zoneMeshes[i].material.color.setHex(STATE_COLOURS[z.state] || 0xffffff);
  });
  if (st.robot) {
    document.getElementById('robot-line').hidden = false;
    document.getElementById('case').textContent = st.active_case;
    document.getElementById('distance').textContent = st.distance_mm === 65535 ? 'none in range' : `${st.distance_mm} mm`;
    document.getElementById('required').textContent = st.required_mm;
  }
  setCapsules(st.capsules || []);
  view.capsules = (st.capsules || []).length;
  if (st.voxels === false) return;  // the first snapshot after nobody watched: no voxel lists yet
  document.getElementById('fg-count').textContent =
    st.foreground_total + (st.foreground_truncated ? ` (first ${st.foreground.length} drawn)` : '');
  document.getElementById('unseen-count').textContent =
    st.unseen_total + (st.unseen_truncated ? ` (first ${st.unseen.length} drawn)` : '');
  if (fgPoints) setPoints(fgPoints, st.foreground);
  if (unseenPoints) setPoints(unseenPoints, st.unseen);
}

function tickLiveness() {
  const live = document.getElementById('live');
  const since = view.lastEventAt === 0 ? Infinity : performance.now() - view.lastEventAt;
  const age = (view.lastAgeMs || 0) + (Number.isFinite(since) ? since : 0);
  document.getElementById('age').textContent = Number.isFinite(since) ? age.toFixed(0) : '-';
  const fresh = since < STALE_MS;
  view.stale = !fresh;
  live.textContent = fresh ? 'live' : (view.lastEventAt === 0 ? 'not connected' : 'STALE: no update');
  live.className = fresh ? 'fresh' : 'stale';
}

async function loadStops() {
  try {
    const note = document.getElementById('stops-note');
    if (grid && grid.snapshots === false) {
      note.textContent = 'No stop history: the monitor runs without --snapshot-dir DIR, so it keeps no ' +
        'snapshot of its protective stops to list here.';
      view.stopsNote = note.textContent;
      return;
    }
    const stops = await (await fetch('/api/stops')).json();
    note.textContent = stops.length === 0 ? 'No protective stop after a release yet (a snapshot is ' +
      'written for each).' : '';
    view.stopsNote = note.textContent;
    const list = document.getElementById('stops');
    const key = stops.map(s => s.sequence).join(',');
    if (list.dataset.key === key) return;
    list.dataset.key = key;
    list.textContent = '';
    stops.forEach(s => {
      const li = document.createElement('li');
      li.textContent = `stop in cycle ${s.cycle} (${s.name})`;
      const img = document.createElement('img');
      img.src = s.picture;
      img.alt = 'snapshot picture of ' + s.name;
      li.appendChild(img);
      list.appendChild(li);
    });
    view.stops = stops.length;
  } catch (e) { view.error = String(e); }
}

view.loadStops = loadStops;  // the headless-browser test asks for the list once a snapshot is on disk
// The headless-browser test draws the first cycle that showed a zone-state set again, after the
// run, when its live screenshot missed it (a loaded host). False when no such cycle was received.
view.replay = key => {
  if (!(key in view.kept)) return false;
  showState(view.kept[key], true);
  return true;
};

async function main() {
  try {
    grid = await (await fetch('/api/static')).json();
    buildTable(grid);
    buildScene(grid);
    view.staticLoaded = true;
  } catch (e) { view.error = String(e); }
  const events = new EventSource('/api/events');
  events.onmessage = m => showState(JSON.parse(m.data));
  setInterval(tickLiveness, 200);
  loadStops();
  setInterval(loadStops, 3000);
}
main();
