// The page of `treeskel ... --html`: the cloud, the skeleton and the mesh of one tree, and its report.
// Bundled with three.js (npm) into one script at build time (view/embed_viewer.js) and inlined into
// every page, so that a page opens from disk with no network.
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';

const BACKGROUND = 0xf7f7f4;
// Branch orders: trunk, then one colour per order (the last repeats).
const ORDER_COLOURS = [0x6b3a1e, 0xd1495b, 0xedae49, 0x00798c, 0x30638e, 0x7b2cbf, 0x2a9d8f];
// What the tool did with each point: in the tree, left out (noise, a small cluster, a far part), leaf.
const CLASS_COLOURS = [0x4f6d7a, 0xe4572e, 0x76b041];

function decodeBase64(text) {
  const clean = text.replace(/\s+/g, '');
  if (typeof Uint8Array.fromBase64 === 'function') return Uint8Array.fromBase64(clean);
  const s = atob(clean);
  const out = new Uint8Array(s.length);
  for (let i = 0; i < s.length; ++i) out[i] = s.charCodeAt(i);
  return out;
}

async function inflate(bytes) {
  const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream('deflate'));
  return new Uint8Array(await new Response(stream).arrayBuffer());
}

// A colour ramp from low (dark blue) through green to high (yellow), for heights and radii.
function ramp(t, out) {
  const stops = [[0.27, 0.0, 0.33], [0.13, 0.57, 0.55], [0.99, 0.91, 0.14]];
  t = Math.min(1, Math.max(0, t));
  const x = t * (stops.length - 1), i = Math.min(stops.length - 2, Math.floor(x)), f = x - i;
  for (let k = 0; k < 3; ++k) out[k] = stops[i][k] * (1 - f) + stops[i + 1][k] * f;
  return out;
}

function setColour(array, i, hex) {
  array[3 * i] = ((hex >> 16) & 255) / 255;
  array[3 * i + 1] = ((hex >> 8) & 255) / 255;
  array[3 * i + 2] = (hex & 255) / 255;
}

function formatNumber(x, digits = 3) {
  if (x === null || x === undefined || Number.isNaN(x)) return 'n/a';
  return Number(x).toPrecision(digits).replace(/\.?0+$/, '').replace(/\.?0+e/, 'e');
}

function element(tag, attributes = {}, text) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attributes)) e.setAttribute(k, v);
  if (text !== undefined) e.textContent = text;
  return e;
}

// The report beside the view: what a forester reads first, then the mesh's checks and the warnings.
function fillPanel(panel, scene) {
  panel.replaceChildren();
  const r = scene.report || {};
  const m = r.measurements || {};
  const mesh = r.mesh || {};
  const units = scene.units ? ' ' + scene.units : '';
  const rows = [];
  if (r.points !== undefined) rows.push(['points', r.points.toLocaleString('en')]);
  if (scene.shownPoints !== undefined && r.points !== undefined && scene.shownPoints < r.points)
    rows.push(['points shown', scene.shownPoints.toLocaleString('en')]);
  if (r.nodes !== undefined) rows.push(['skeleton nodes', r.nodes.toLocaleString('en')]);
  if (m.height !== undefined) rows.push(['height', formatNumber(m.height) + units]);
  if (m.dbh !== undefined) {
    let dbh = m.dbh === null ? 'n/a' : formatNumber(m.dbh) + units;
    if (m.dbh !== null && m.dbh_height !== undefined) dbh += ' at ' + formatNumber(m.dbh_height) + units;
    if (m.dbh_source) dbh += m.dbh_source === 'points' ? ' (fitted to the points)' : m.dbh_source === 'model' ? ' (from the model)' : '';
    rows.push(['DBH', dbh]);
  }
  if (m.volume !== undefined) rows.push(['wood volume', formatNumber(m.volume) + (units ? units + '³' : '')]);
  if (mesh.volume !== undefined) rows.push(['mesh volume', formatNumber(mesh.volume) + (units ? units + '³' : '')]);
  if (mesh.skeleton_coverage !== undefined)
    rows.push(['skeleton inside the mesh', (100 * mesh.skeleton_coverage).toFixed(1) + '%']);
  if (mesh.triangles !== undefined) rows.push(['triangles', mesh.triangles.toLocaleString('en')]);
  if (mesh.components !== undefined) rows.push(['components', String(mesh.components)]);
  if (r.branch_points !== undefined) rows.push(['branch points', String(r.branch_points)]);
  if (r.endpoints !== undefined) rows.push(['endpoints', String(r.endpoints)]);
  if (Array.isArray(m.branches_by_order))
    rows.push(['branches by order', m.branches_by_order.map((n, k) => k + ': ' + n).join(', ')]);
  if (r.left_out && r.left_out.total !== undefined) rows.push(['points left out', r.left_out.total.toLocaleString('en')]);
  const table = element('table', { id: 'report' });
  for (const [k, v] of rows) {
    const tr = element('tr');
    tr.append(element('th', {}, k), element('td', {}, v));
    table.append(tr);
  }
  panel.append(table);
  const warnings = r.warnings || [];
  const list = element('ul', { id: 'warnings' });
  for (const w of warnings) list.append(element('li', {}, w));
  if (warnings.length > 0) panel.append(element('h2', {}, 'Warnings'), list);
}

// The legend of the colours in use.
function legend(box, entries) {
  box.replaceChildren();
  for (const [hex, label] of entries) {
    const item = element('span', { class: 'key' });
    const swatch = element('i');
    swatch.style.background = '#' + hex.toString(16).padStart(6, '0');
    item.append(swatch, document.createTextNode(label));
    box.append(item);
  }
}

async function main() {
  const timing = { start: performance.now() };
  const manifest = JSON.parse(document.getElementById('treeskel-scene').textContent);
  const raw = decodeBase64(document.getElementById('treeskel-data').textContent);
  const bytes = manifest.compressed ? await inflate(raw) : raw;
  const buffer = bytes.buffer;
  timing.decoded = performance.now();
  const view = (type, entry) => (entry ? new type(buffer, entry.offset, entry.count) : new type(0));
  // Positions are 16-bit steps across the scene's box.
  const positions = (entry) => {
    if (!entry) return new Float32Array(0);
    const q = view(Uint16Array, entry);
    const out = new Float32Array(q.length);
    for (let i = 0; i < q.length; ++i) out[i] = entry.min[i % 3] + q[i] * entry.step[i % 3];
    return out;
  };
  const points = positions(manifest.arrays.points);
  const classes = view(Uint8Array, manifest.arrays.classes);
  const segments = positions(manifest.arrays.segments);
  const segmentOrders = view(Uint8Array, manifest.arrays.segment_orders);
  const segmentRadii = view(Float32Array, manifest.arrays.segment_radii);
  const vertices = positions(manifest.arrays.vertices);
  const triangles = view(Uint32Array, manifest.arrays.triangles);

  const preview = location.hash === '#preview';
  document.body.classList.toggle('preview', preview);
  const up = new THREE.Vector3(...manifest.up).normalize();
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(BACKGROUND);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x8a7a66, 2.2));
  const sun = new THREE.DirectionalLight(0xffffff, 1.6);
  sun.position.copy(up).multiplyScalar(2).add(new THREE.Vector3(1, 1, 1).sub(up));
  scene.add(sun);

  // The tree's box, for the camera and the height colours.
  const box = new THREE.Box3();
  const grow = (array) => {
    for (let i = 0; i + 2 < array.length; i += 3) box.expandByPoint(new THREE.Vector3(array[i], array[i + 1], array[i + 2]));
  };
  grow(points);
  grow(segments);
  grow(vertices);
  if (box.isEmpty()) box.expandByPoint(new THREE.Vector3());
  const centre = box.getCenter(new THREE.Vector3());
  const size = box.getSize(new THREE.Vector3());
  const radius = Math.max(size.length() / 2, 1e-9);
  const low = Math.min(...[box.min, box.max].map((c) => c.dot(up)));
  const high = Math.max(...[box.min, box.max].map((c) => c.dot(up)));

  // The cloud.
  const cloudGeometry = new THREE.BufferGeometry();
  cloudGeometry.setAttribute('position', new THREE.BufferAttribute(points, 3));
  const cloudColours = new Float32Array(points.length);
  cloudGeometry.setAttribute('color', new THREE.BufferAttribute(cloudColours, 3));
  const cloudMaterial = new THREE.PointsMaterial({ size: 2, sizeAttenuation: false, vertexColors: true });
  const cloud = new THREE.Points(cloudGeometry, cloudMaterial);
  const colourCloud = (mode) => {
    const c = [0, 0, 0];
    const p = new THREE.Vector3();
    for (let i = 0; i < points.length / 3; ++i) {
      if (mode === 'status') {
        setColour(cloudColours, i, CLASS_COLOURS[classes[i]] ?? CLASS_COLOURS[0]);
      } else {
        p.set(points[3 * i], points[3 * i + 1], points[3 * i + 2]);
        ramp((p.dot(up) - low) / Math.max(high - low, 1e-12), c);
        cloudColours.set(c, 3 * i);
      }
    }
    cloudGeometry.attributes.color.needsUpdate = true;
  };

  // The skeleton, as lines.
  const skeletonGeometry = new THREE.BufferGeometry();
  skeletonGeometry.setAttribute('position', new THREE.BufferAttribute(segments, 3));
  const skeletonColours = new Float32Array(segments.length);
  skeletonGeometry.setAttribute('color', new THREE.BufferAttribute(skeletonColours, 3));
  const skeleton = new THREE.LineSegments(skeletonGeometry, new THREE.LineBasicMaterial({ vertexColors: true }));
  let maxRadius = 0;
  for (const r of segmentRadii) maxRadius = Math.max(maxRadius, r);
  const colourSkeleton = (mode) => {
    const c = [0, 0, 0];
    for (let s = 0; s < segments.length / 6; ++s) {
      if (mode === 'radius' && maxRadius > 0) {
        ramp(Math.sqrt(segmentRadii[s] / maxRadius), c);
        skeletonColours.set(c, 6 * s);
        skeletonColours.set(c, 6 * s + 3);
      } else {
        const hex = ORDER_COLOURS[Math.min(segmentOrders[s] ?? 0, ORDER_COLOURS.length - 1)];
        setColour(skeletonColours, 2 * s, hex);
        setColour(skeletonColours, 2 * s + 1, hex);
      }
    }
    skeletonGeometry.attributes.color.needsUpdate = true;
  };

  // The mesh, semi-transparent so that the skeleton shows through.
  const meshGeometry = new THREE.BufferGeometry();
  meshGeometry.setAttribute('position', new THREE.BufferAttribute(vertices, 3));
  meshGeometry.setIndex(new THREE.BufferAttribute(triangles, 1));
  meshGeometry.computeVertexNormals();
  const meshMaterial = new THREE.MeshStandardMaterial({
    color: 0x9c7b5b, roughness: 0.9, metalness: 0.0, transparent: true, opacity: 0.55, depthWrite: false, side: THREE.DoubleSide,
  });
  const mesh = new THREE.Mesh(meshGeometry, meshMaterial);
  mesh.renderOrder = 1;
  if (preview) {
    cloudMaterial.size = 1.5;
    meshMaterial.opacity = 0.7;
  }
  scene.add(cloud, skeleton, mesh);

  // Controls: what is shown and how it is coloured.
  const panel = document.getElementById('details');
  const controls = document.getElementById('controls');
  const legendBox = document.getElementById('legend');
  const have = { cloud: points.length > 0, skeleton: segments.length > 0, mesh: triangles.length > 0 };
  const toggles = {};
  for (const [name, object] of [['cloud', cloud], ['skeleton', skeleton], ['mesh', mesh]]) {
    const label = element('label');
    const box = element('input', { type: 'checkbox', id: 'show-' + name });
    box.checked = have[name];
    box.disabled = !have[name];
    object.visible = box.checked;
    label.append(box, document.createTextNode(' ' + name));
    controls.append(label);
    toggles[name] = box;
  }
  const select = (id, options) => {
    const s = element('select', { id });
    for (const [value, text] of options) s.append(element('option', { value }, text));
    controls.append(s);
    return s;
  };
  const cloudMode = select('cloud-colour', [['status', 'points by what the tool did'], ['height', 'points by height']]);
  const skeletonMode = select('skeleton-colour', [['order', 'skeleton by branch order'], ['radius', 'skeleton by radius']]);
  const updateLegend = () => {
    const entries = [];
    if (toggles.cloud.checked && cloudMode.value === 'status') {
      entries.push([CLASS_COLOURS[0], 'in the tree'], [CLASS_COLOURS[1], 'left out']);
      if (classes.some((c) => c === 2)) entries.push([CLASS_COLOURS[2], 'leaf']);
    }
    if (toggles.skeleton.checked && skeletonMode.value === 'order') {
      let top = 0;
      for (const o of segmentOrders) top = Math.max(top, o);
      for (let k = 0; k <= Math.min(top, ORDER_COLOURS.length - 1); ++k)
        entries.push([ORDER_COLOURS[k], k === 0 ? 'trunk' : 'order ' + k + (k === ORDER_COLOURS.length - 1 && top > k ? '+' : '')]);
    }
    legend(legendBox, entries);
  };
  colourCloud(cloudMode.value);
  colourSkeleton(skeletonMode.value);
  updateLegend();
  fillPanel(panel, { report: manifest.report, units: manifest.units, shownPoints: points.length / 3 });
  document.getElementById('title').textContent = manifest.title;
  const caption = document.getElementById('caption');
  const m = (manifest.report && manifest.report.measurements) || {};
  const parts = [manifest.title];
  if (m.height !== undefined) parts.push('height ' + formatNumber(m.height));
  if (m.dbh !== undefined && m.dbh !== null) parts.push('DBH ' + formatNumber(m.dbh));
  if (m.volume !== undefined) parts.push('wood volume ' + formatNumber(m.volume));
  const r = manifest.report || {};
  if (m.height === undefined) {
    if (r.points !== undefined) parts.push(r.points.toLocaleString('en') + ' points');
    if (r.nodes !== undefined) parts.push(r.nodes.toLocaleString('en') + ' skeleton nodes');
    if (r.branch_points !== undefined) parts.push(r.branch_points + ' branch points');
  }
  if (r.mesh && r.mesh.triangles !== undefined) parts.push(r.mesh.triangles.toLocaleString('en') + ' triangles');
  if (r.mesh && r.mesh.skeleton_coverage !== undefined) parts.push((100 * r.mesh.skeleton_coverage).toFixed(0) + '% of the skeleton inside');
  if (Array.isArray(r.warnings) && r.warnings.length > 0) parts.push(r.warnings.length + (r.warnings.length === 1 ? ' warning' : ' warnings'));
  caption.textContent = parts.join(' · ');

  const renderer = new THREE.WebGLRenderer({ canvas: document.getElementById('view'), antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  renderer.setScissorTest(true);
  const camera = new THREE.PerspectiveCamera(35, 1, radius * 1e-3, radius * 100);
  camera.up.copy(up);
  // A side that the tree's up axis is not: the camera looks along it from the front.
  const side = Math.abs(up.y) > 0.9 ? new THREE.Vector3(0, 0, 1) : new THREE.Vector3(0, -1, 0).sub(up.clone().multiplyScalar(-up.y)).normalize();
  // Far enough that the box fills the view: its extent along `up` and across it, seen from `from`.
  const fit = (from, vertical, aspect) => {
    const across = new THREE.Vector3().crossVectors(vertical, from).normalize();
    const extent = (axis) => Math.abs(size.x * axis.x) + Math.abs(size.y * axis.y) + Math.abs(size.z * axis.z);
    const t = Math.tan(THREE.MathUtils.degToRad(35 / 2));
    return Math.max(extent(vertical) / 2 / t, extent(across) / 2 / (t * aspect)) * 1.08 + extent(from) / 2;
  };
  const place = (cam, from, vertical, aspect) => {
    cam.position.copy(centre).add(from.clone().multiplyScalar(fit(from, vertical, aspect)));
    cam.lookAt(centre);
  };
  const initialAspect = () => {
    const c = document.getElementById('view');
    return (preview ? c.clientWidth / 2 : c.clientWidth) / Math.max(c.clientHeight, 1);
  };
  place(camera, side, up, initialAspect());
  const orbit = new OrbitControls(camera, renderer.domElement);
  orbit.target.copy(centre);
  orbit.update();
  // The view from above, for the preview.
  const topCamera = new THREE.PerspectiveCamera(35, 1, radius * 1e-3, radius * 100);
  topCamera.up.copy(side.clone().negate());
  place(topCamera, up, side.clone().negate(), initialAspect());
  const render = () => {
    const canvas = renderer.domElement;
    const width = canvas.clientWidth, height = canvas.clientHeight;
    if (canvas.width !== Math.round(width * renderer.getPixelRatio()) || canvas.height !== Math.round(height * renderer.getPixelRatio()))
      renderer.setSize(width, height, false);
    if (preview) {
      const half = Math.floor(width / 2);
      for (const [cam, x, w] of [[camera, 0, half], [topCamera, half, width - half]]) {
        cam.aspect = w / height;
        cam.updateProjectionMatrix();
        renderer.setViewport(x, 0, w, height);
        renderer.setScissor(x, 0, w, height);
        renderer.render(scene, cam);
      }
    } else {
      camera.aspect = width / Math.max(height, 1);
      camera.updateProjectionMatrix();
      renderer.setViewport(0, 0, width, height);
      renderer.setScissor(0, 0, width, height);
      renderer.render(scene, camera);
    }
  };
  orbit.addEventListener('change', render);
  window.addEventListener('resize', render);
  for (const [name, object] of [['cloud', cloud], ['skeleton', skeleton], ['mesh', mesh]])
    toggles[name].addEventListener('change', () => {
      object.visible = toggles[name].checked;
      updateLegend();
      render();
    });
  cloudMode.addEventListener('change', () => { colourCloud(cloudMode.value); updateLegend(); render(); });
  skeletonMode.addEventListener('change', () => { colourSkeleton(skeletonMode.value); updateLegend(); render(); });
  timing.built = performance.now();
  render();
  timing.drawn = performance.now();
  // For tests and for the preview: the page has drawn its first frame.
  window.treeskel = {
    ready: true,
    counts: { points: points.length / 3, segments: segments.length / 6, triangles: triangles.length / 3 },
    render,
    timing,
  };
  document.body.dataset.ready = 'true';
}

main().catch((error) => {
  const box = document.getElementById('error');
  box.textContent = 'This page could not show the tree: ' + error.message;
  box.hidden = false;
  console.error(error);
});
