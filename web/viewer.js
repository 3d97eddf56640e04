// The medspheres viewer: the page's JSON scene (parts: a mesh, inner and outer spheres
// and the red pieces of uncovered surface) drawn with three.js and orbit controls.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

const COLORS = { mesh: 0xafafaa, uncovered: 0xe11e1e, inner: 0x3c6edc, outer: 0x2ca05a };

// A typed array the page carries as base64 of its little-endian bytes.
function unpack(text, Type) {
  const bytes = Uint8Array.from(atob(text), (c) => c.charCodeAt(0));
  return new Type(bytes.buffer);
}

// 16-bit coordinates over the part's box back to floats (src/render/view_data.h): each
// within half a step, (box side) / 65535, of the point written.
function dequantize(text, box) {
  const q = unpack(text, Uint16Array);
  const out = new Float32Array(q.length);
  const step = [0, 1, 2].map((k) => (box[k + 3] - box[k]) / 65535);
  for (let i = 0; i < q.length; ++i) out[i] = box[i % 3] + q[i] * step[i % 3];
  return out;
}

// A part's arrays, decoded: positions and indices of its mesh, its spheres as [x, y, z, r]
// rows, and per set the corners of its uncovered pieces (whole triangles and smaller ones).
function decodePart(p) {
  const positions = dequantize(p.positions, p.box);
  const index = unpack(p.triangles, p.index_bytes === 2 ? Uint16Array : Uint32Array);
  const rows = (text) => {
    const f = unpack(text, Float32Array);
    return Array.from({ length: f.length / 4 }, (_, i) => Array.from(f.subarray(4 * i, 4 * i + 4)));
  };
  const uncovered = (u) => {
    const bits = unpack(u.whole, Uint8Array);
    const pieces = dequantize(u.pieces, p.box);
    let whole = 0;
    for (let t = 0; t < p.triangle_count; ++t) whole += (bits[t >> 3] >> (t & 7)) & 1;
    const corners = new Float32Array(9 * whole + pieces.length);
    let at = 0;
    for (let t = 0; t < p.triangle_count; ++t) {
      if (!((bits[t >> 3] >> (t & 7)) & 1)) continue;
      for (let k = 0; k < 3; ++k) corners.set(positions.subarray(3 * index[3 * t + k], 3 * index[3 * t + k] + 3), at + 3 * k);
      at += 9;
    }
    corners.set(pieces, at);
    return corners;
  };
  return { name: p.name, triangle_count: p.triangle_count, positions, index,
    inner: rows(p.inner), outer: rows(p.outer),
    uncovered_inner: uncovered(p.uncovered_inner), uncovered_outer: uncovered(p.uncovered_outer) };
}

// What the page decoded, for a test to compare with the mesh it wrote: vertices,
// triangles, the box and the mean of every vertex, the area of the triangles, uncovered
// triangle pieces per set.
function geometrySummary(parts) {
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  const sum = [0, 0, 0];
  let vertices = 0, triangles = 0, area = 0, inner = 0, outer = 0;
  for (const p of parts) {
    vertices += p.positions.length / 3;
    triangles += p.index.length / 3;
    inner += p.uncovered_inner.length / 9;
    outer += p.uncovered_outer.length / 9;
    const x = p.positions;
    for (let i = 0; i < x.length; ++i) {
      lo[i % 3] = Math.min(lo[i % 3], x[i]);
      hi[i % 3] = Math.max(hi[i % 3], x[i]);
      sum[i % 3] += x[i];
    }
    for (let t = 0; t < p.index.length; t += 3) {
      const [a, b, c] = [3 * p.index[t], 3 * p.index[t + 1], 3 * p.index[t + 2]];
      const u = [0, 1, 2].map((k) => x[b + k] - x[a + k]), v = [0, 1, 2].map((k) => x[c + k] - x[a + k]);
      area += 0.5 * Math.hypot(u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]);
    }
  }
  return { vertices, triangles, box: [...lo, ...hi], mean: sum.map((s) => s / Math.max(vertices, 1)),
    area, uncovered: { inner, outer } };
}

// "1 part", "2 parts": a count with its noun in the singular for one.
function counted(n, noun) {
  return `${n} ${noun}${n === 1 ? '' : 's'}`;
}

function setStatus(text) {
  document.body.dataset.status = text;
  document.getElementById('status').textContent = text;
}

function meshObject(part) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(part.positions, 3));
  g.setIndex(new THREE.BufferAttribute(part.index, 1));
  g.computeVertexNormals();
  const m = new THREE.MeshLambertMaterial({ color: COLORS.mesh, transparent: true, opacity: 0.45,
    depthWrite: false, side: THREE.DoubleSide });
  return new THREE.Mesh(g, m);
}

function piecesObject(corners) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(corners, 3));
  g.computeVertexNormals();
  const m = new THREE.MeshLambertMaterial({ color: COLORS.uncovered, transparent: true,
    opacity: 0.65, side: THREE.DoubleSide, polygonOffset: true, polygonOffsetFactor: -1,
    polygonOffsetUnits: -1 });
  return new THREE.Mesh(g, m);
}

function spheresObject(spheres, color, opacity, part, kind) {
  const geometry = new THREE.SphereGeometry(1, 24, 16);
  const material = new THREE.MeshLambertMaterial({ color, transparent: opacity < 1, opacity });
  const object = new THREE.InstancedMesh(geometry, material, spheres.length);
  const m = new THREE.Matrix4();
  spheres.forEach(([x, y, z, r], i) => {
    m.makeScale(r, r, r).setPosition(x, y, z);
    object.setMatrixAt(i, m);
  });
  object.userData = { spheres, part, kind };
  object.computeBoundingSphere();
  return object;
}

function checkbox(parent, text, checked, onChange, color) {
  const label = document.createElement('label');
  const box = document.createElement('input');
  box.type = 'checkbox';
  box.checked = checked;
  box.addEventListener('change', () => onChange(box.checked));
  label.appendChild(box);
  if (color !== undefined) {
    const swatch = document.createElement('span');
    swatch.className = 'swatch';
    swatch.style.background = '#' + color.toString(16).padStart(6, '0');
    label.appendChild(swatch);
  }
  label.appendChild(document.createTextNode(text));
  parent.appendChild(label);
  return box;
}

function main() {
  const data = JSON.parse(document.getElementById('medspheres-data').textContent);
  data.parts = data.parts.map(decodePart);
  document.body.dataset.geometry = JSON.stringify(geometrySummary(data.parts));
  const host = document.getElementById('view');
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio);
  renderer.setSize(host.clientWidth, host.clientHeight);
  host.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xffffff);
  // The robot convention: z up.
  const camera = new THREE.PerspectiveCamera(35, host.clientWidth / host.clientHeight, 1e-3, 1e3);
  camera.up.set(0, 0, 1);
  scene.add(new THREE.AmbientLight(0xffffff, 1.2));
  const light = new THREE.DirectionalLight(0xffffff, 1.8);
  light.position.set(-0.3, 0.4, 1);
  camera.add(light);
  scene.add(camera);

  const show = { mesh: true, inner: true, outer: true, uncovered: true };
  const parts = data.parts.map((p) => {
    const group = new THREE.Group();
    const o = { group, name: p.name, inner: null, outer: null, mesh: null, red: {} };
    if (p.triangle_count > 0) group.add(o.mesh = meshObject(p));
    for (const kind of ['inner', 'outer']) {
      const red = p['uncovered_' + kind];
      if (red.length > 0) group.add(o.red[kind] = piecesObject(red));
      if (p[kind].length > 0)
        group.add(o[kind] = spheresObject(p[kind], COLORS[kind], kind === 'inner' ? 0.6 : 0.3, p.name, kind));
    }
    scene.add(group);
    return o;
  });
  const count = (kind) => data.parts.reduce((n, p) => n + p[kind].length, 0);
  const triangles = data.parts.reduce((n, p) => n + p.triangle_count, 0);

  const draw = () => renderer.render(scene, camera);
  const update = () => {
    for (const o of parts) {
      if (o.mesh) o.mesh.visible = show.mesh;
      for (const kind of ['inner', 'outer']) if (o[kind]) o[kind].visible = show[kind];
      // The colouring of the outermost set shown.
      const kind = show.outer && o.outer ? 'outer' : show.inner && o.inner ? 'inner' : null;
      for (const k of ['inner', 'outer'])
        if (o.red[k]) o.red[k].visible = show.mesh && show.uncovered && k === kind;
    }
    draw();
  };

  const panel = document.getElementById('panel');
  const title = document.createElement('b');
  title.textContent = data.title;
  panel.appendChild(title);
  if (data.warning) {
    const w = document.createElement('div');
    w.className = 'warning';
    w.textContent = 'warning: ' + data.warning;
    panel.appendChild(w);
  }
  checkbox(panel, `mesh (${counted(triangles, 'triangle')})`, true, (v) => { show.mesh = v; update(); }, COLORS.mesh);
  checkbox(panel, 'uncovered surface', true, (v) => { show.uncovered = v; update(); }, COLORS.uncovered);
  checkbox(panel, `inner spheres (${count('inner')})`, true, (v) => { show.inner = v; update(); }, COLORS.inner);
  checkbox(panel, `outer spheres (${count('outer')})`, true, (v) => { show.outer = v; update(); }, COLORS.outer);
  if (parts.length > 1 || (parts.length === 1 && parts[0].name)) {
    // A list to open: a robot's links would hide the robot.
    const links = document.createElement('details');
    links.className = 'links';
    links.open = parts.length <= 6;
    const summary = document.createElement('summary');
    summary.textContent = `links (${parts.length})`;
    links.appendChild(summary);
    for (const o of parts) checkbox(links, o.name, true, (v) => { o.group.visible = v; draw(); });
    panel.appendChild(links);
  }

  // The rows below the panel, where the view is framed when the panel leaves at least half
  // of the window (a long title or warning can span its width): the projection's centre
  // moves to the middle of those rows. Returns how much farther the camera must stand for
  // a fit in them than in the whole window.
  const frameBelowPanel = () => {
    const width = host.clientWidth, height = host.clientHeight;
    const bottom = panel.getBoundingClientRect().bottom;
    const top = bottom < height / 2 ? Math.max(0, bottom) : 0;
    camera.aspect = width / (height + top);
    camera.setViewOffset(width, height + top, 0, 0, width, height);
    camera.updateProjectionMatrix();
    return (height + top) / (height - top);
  };

  // Frame everything: the box of all parts, seen from (+1, -1, +1) like render's iso view.
  const box = new THREE.Box3();
  for (const o of parts) box.expandByObject(o.group);
  const center = box.isEmpty() ? new THREE.Vector3() : box.getCenter(new THREE.Vector3());
  const radius = box.isEmpty() ? 1 : Math.max(box.getSize(new THREE.Vector3()).length() / 2, 1e-6);
  const distance =
    frameBelowPanel() * 1.1 * radius / Math.sin(THREE.MathUtils.degToRad(camera.fov / 2));
  camera.position.copy(center).add(new THREE.Vector3(1, -1, 1).normalize().multiplyScalar(distance));
  camera.near = distance / 100;
  camera.far = distance * 100;
  camera.updateProjectionMatrix();
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.target.copy(center);
  controls.update();
  controls.addEventListener('change', draw);

  // The sphere under the mouse.
  const raycaster = new THREE.Raycaster();
  const pointer = new THREE.Vector2();
  const hover = document.getElementById('hover');
  renderer.domElement.addEventListener('pointermove', (e) => {
    const r = renderer.domElement.getBoundingClientRect();
    pointer.set(((e.clientX - r.left) / r.width) * 2 - 1, -((e.clientY - r.top) / r.height) * 2 + 1);
    raycaster.setFromCamera(pointer, camera);
    const targets = [];
    for (const o of parts)
      if (o.group.visible) for (const k of ['inner', 'outer']) if (o[k] && o[k].visible) targets.push(o[k]);
    const hit = raycaster.intersectObjects(targets, false)[0];
    if (!hit) { hover.textContent = ''; return; }
    const { spheres, part, kind } = hit.object.userData;
    const [x, y, z, s] = spheres[hit.instanceId];
    hover.textContent = `${part ? part + ' ' : ''}${kind} sphere ${hit.instanceId}: centre (${x}, ${y}, ${z}), radius ${s}`;
  });
  window.addEventListener('resize', () => {
    frameBelowPanel();
    renderer.setSize(host.clientWidth, host.clientHeight);
    draw();
  });
  update();
  setStatus(`ok: three.js r${THREE.REVISION}, ${counted(parts.length, 'part')}, ` +
            `${counted(triangles, 'triangle')}, ${count('inner')} inner and ` +
            `${count('outer')} outer spheres`);
}

try {
  main();
} catch (e) {
  setStatus('error: ' + e.message);
  throw e;
}
