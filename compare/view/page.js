// The replay page's script: decodes the data `lockstep` inlined, draws every
// run's boxes with instanced meshes (three.js), the charts (Chart.js), and
// links both to the frame slider. window.lockstepView is what the browser
// test (tests/compare/view_browser_test.py) drives.
(function () {
  'use strict';
  const started = performance.now();
  const D = JSON.parse(document.getElementById('lockstep-data').textContent);
  const $ = (id) => document.getElementById(id);

  function decode(text, Type) {
    const bin = atob(text);
    const bytes = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; ++i) bytes[i] = bin.charCodeAt(i);
    return Type === Uint8Array ? bytes : new Type(bytes.buffer);
  }

  const S = D.scene;
  const N = S.bodies;
  const FLOATS = 13;  // p (3), q (w, x, y, z), v (3), w (3)
  const half = decode(S.half_extents, Float32Array);
  const isStatic = decode(S.static, Uint8Array);
  const runs = D.runs.map((r) => Object.assign({}, r, {
    state: decode(r.state, Float32Array),
    asleepBits: decode(r.asleep, Uint8Array),
  }));
  const C = D.comparison || null;
  const REC = D.recording || null;  // a recording replayed: its inputs and where the replay diverged
  const ABSENT = 2;  // a body's asleep byte when it does not exist at that frame (a recording's creations, removals)
  const base = runs[0];
  const keptFrames = base.frames;  // the slider walks the baseline's kept frames
  const COLORS = ['#4f9dff', '#ff9f40', '#4bc07a', '#c77dff', '#ffd24d', '#ff6b9a', '#6fe0e0'];
  const STATE_COLORS = { awake: 0x4f9dff, asleep: 0x8a7fb0, static: 0x6b6f78, diverged: 0xff3b3b };

  // A per-frame series' value at frame f (series keep one frame in
  // series_every on very long runs); undefined when not kept.
  function seriesAt(run, name, f) {
    const every = run.series_every || 1, v = run[name];
    return v && f % every === 0 ? v[f / every] : undefined;
  }

  // The kept-frame index of run r at or before frame f.
  function indexAt(run, f) {
    const fr = run.frames;
    let lo = 0, hi = fr.length - 1;
    if (hi < 0) return -1;
    while (lo < hi) {
      const mid = (lo + hi + 1) >> 1;
      if (fr[mid] <= f) lo = mid; else hi = mid - 1;
    }
    return lo;
  }

  // #only=GROUP and #run=R (the browser test): draw only the boxes of one
  // group (awake, asleep, static, diverged) and/or of one run, on the bare
  // background (no ground, grid or SDF).
  const params = new URLSearchParams(location.hash.slice(1));
  const onlyKind = params.get('only');
  const onlyRun = params.has('run') ? +params.get('run') : null;
  const isolated = onlyKind !== null || onlyRun !== null;

  // ---- three.js scene -------------------------------------------------------
  // Without WebGL (no GPU, WebGL off) the 3D view is a message; the charts,
  // the slider and the body panel still work.
  const container = $('view3d');
  // Isolated (the browser test): a 3D view of a fixed size, so that a
  // screenshot and the status of another load of the page agree on it.
  if (isolated) { container.style.flex = 'none'; container.style.height = '540px'; }
  let renderer = null, webglError = null;
  {
    const before = window.lockstepErrors.length;
    try {
      renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    } catch (e) {
      webglError = String(e && e.message || e);
    }
    if (!renderer) window.lockstepErrors.splice(before);  // reported as webgl: false, not as an error
  }
  if (renderer) {
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    renderer.setClearColor(0x1d1f24);
    container.appendChild(renderer.domElement);
  } else {
    const msg = document.createElement('div');
    msg.id = 'no-webgl';
    msg.textContent = 'The 3D view needs WebGL, which this browser could not start (' + webglError + '). ' +
      'The charts, the slider and the body panel below work without it; to see the boxes, open this page in a ' +
      'browser with WebGL enabled (chrome://gpu or about:support tells whether it is).';
    container.appendChild(msg);
  }
  const scene = new THREE.Scene();
  scene.add(new THREE.HemisphereLight(0xffffff, 0x404050, 0.75));
  const sun = new THREE.DirectionalLight(0xffffff, 0.6);
  sun.position.set(0.5, 1, 0.8);
  scene.add(sun);

  // Bounds of the scene at frame 0 (for the camera and the ground's size).
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < N; ++i)
    for (let a = 0; a < 3; ++a) {
      const p = base.state[i * FLOATS + a];
      lo[a] = Math.min(lo[a], p - half[3 * i + a]);
      hi[a] = Math.max(hi[a], p + half[3 * i + a]);
    }
  for (const sdf of S.sdfs)
    for (let a = 0; a < 3; ++a) { lo[a] = Math.min(lo[a], sdf.min[a]); hi[a] = Math.max(hi[a], sdf.max[a]); }
  if (!isFinite(lo[0])) { lo.fill(-1); hi.fill(1); }
  const center = new THREE.Vector3((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2);
  const radius = Math.max(1, 0.5 * Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]));

  if (S.ground.present && !isolated) {
    const size = Math.max(20, 4 * radius);
    const plane = new THREE.Mesh(new THREE.PlaneBufferGeometry(size, size),
      new THREE.MeshLambertMaterial({ color: 0x3a3d44, side: THREE.DoubleSide }));
    plane.rotation.x = -Math.PI / 2;
    plane.position.set(center.x, S.ground.height - 0.001, center.z);
    scene.add(plane);
    const grid = new THREE.GridHelper(size, Math.min(200, Math.round(size)), 0x555a66, 0x464a54);
    grid.position.set(center.x, S.ground.height, center.z);
    scene.add(grid);
  }
  // SDF volumes: their bounds and the samples on the solid's surface (inside,
  // next to an outside sample).
  for (const sdf of (isolated ? [] : S.sdfs)) {
    const v = decode(sdf.values, Float32Array);
    const [nx, ny, nz] = sdf.n;
    const at = (i, j, k) => v[i + nx * (j + ny * k)];
    const pts = [];
    for (let k = 0; k < nz; ++k)
      for (let j = 0; j < ny; ++j)
        for (let i = 0; i < nx; ++i) {
          if (at(i, j, k) > 0) continue;
          let surface = false;
          for (const [di, dj, dk] of [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]]) {
            const a = i + di, b = j + dj, c = k + dk;
            if (a >= 0 && b >= 0 && c >= 0 && a < nx && b < ny && c < nz && at(a, b, c) > 0) surface = true;
          }
          if (!surface) continue;
          pts.push(sdf.min[0] + (sdf.max[0] - sdf.min[0]) * i / (nx - 1),
                   sdf.min[1] + (sdf.max[1] - sdf.min[1]) * j / (ny - 1),
                   sdf.min[2] + (sdf.max[2] - sdf.min[2]) * k / (nz - 1));
        }
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute(pts, 3));
    scene.add(new THREE.Points(g, new THREE.PointsMaterial({ color: 0x9bb86b, size: 0.06 })));
    const box = new THREE.Box3(new THREE.Vector3(...sdf.min), new THREE.Vector3(...sdf.max));
    scene.add(new THREE.Box3Helper(box, 0x6b7d4b));
  }

  // Each run: one instanced mesh per body state (awake, asleep, static,
  // beyond the tolerance), re-filled every frame. Every instanced mesh has
  // its own box geometry: three.js r111 (Debian's libjs-three) binds the
  // instance matrices only when the geometry or program changes between two
  // draws, so meshes sharing one geometry and material program would all be
  // drawn with the first one's matrices (the others' boxes missing).
  const unitBox = new THREE.BoxBufferGeometry(1, 1, 1);
  const edges = new THREE.EdgesGeometry(unitBox);
  for (const [r, run] of runs.entries()) {
    run.group = new THREE.Group();
    run.meshes = {};
    const ghost = r > 0;
    for (const kind of ['awake', 'asleep', 'static', 'diverged']) {
      const mat = new THREE.MeshLambertMaterial({ color: STATE_COLORS[kind] });
      if (ghost && kind !== 'diverged') {
        mat.color.lerp(new THREE.Color(COLORS[r % COLORS.length]), 0.5);
      }
      const mesh = new THREE.InstancedMesh(new THREE.BoxBufferGeometry(1, 1, 1), mat, Math.max(1, N));
      // A group left out by #only/#run is still drawn, writing no colour and
      // no depth: the draw calls are those of the whole page, so the test
      // sees what the page draws (r111's binding depends on the order).
      mesh.userData.shown = (onlyKind === null || onlyKind === kind) && (onlyRun === null || onlyRun === r);
      if (mesh.instanceMatrix.setUsage) mesh.instanceMatrix.setUsage(THREE.DynamicDrawUsage);
      mesh.frustumCulled = false;
      mesh.count = 0;
      run.meshes[kind] = mesh;
      run.group.add(mesh);
    }
    scene.add(run.group);
  }
  const selection = new THREE.LineSegments(edges, new THREE.LineBasicMaterial({ color: 0xffff00 }));
  selection.matrixAutoUpdate = false;
  selection.visible = false;
  scene.add(selection);

  const camera = new THREE.PerspectiveCamera(45, 1, 0.05, 2000 + 20 * radius);
  camera.position.set(center.x + 1.3 * radius * 1.2, center.y + 0.9 * radius * 1.2, center.z + 1.6 * radius * 1.2);
  camera.lookAt(center);
  const controls = renderer ? new THREE.OrbitControls(camera, renderer.domElement) : null;
  if (controls) {
    controls.target.copy(center);
    controls.update();
  }

  // A body's world matrix (three.js column-major) into out[o..o+15].
  function bodyMatrix(run, k, i, out, o) {
    const s = (k * N + i) * FLOATS, st = run.state;
    const px = st[s], py = st[s + 1], pz = st[s + 2];
    const w = st[s + 3], x = st[s + 4], y = st[s + 5], z = st[s + 6];
    const sx = 2 * half[3 * i], sy = 2 * half[3 * i + 1], sz = 2 * half[3 * i + 2];
    const x2 = x + x, y2 = y + y, z2 = z + z;
    const xx = x * x2, xy = x * y2, xz = x * z2, yy = y * y2, yz = y * z2, zz = z * z2;
    const wx = w * x2, wy = w * y2, wz = w * z2;
    out[o] = (1 - (yy + zz)) * sx; out[o + 1] = (xy + wz) * sx; out[o + 2] = (xz - wy) * sx; out[o + 3] = 0;
    out[o + 4] = (xy - wz) * sy; out[o + 5] = (1 - (xx + zz)) * sy; out[o + 6] = (yz + wx) * sy; out[o + 7] = 0;
    out[o + 8] = (xz + wy) * sz; out[o + 9] = (yz - wx) * sz; out[o + 10] = (1 - (xx + yy)) * sz; out[o + 11] = 0;
    out[o + 12] = px; out[o + 13] = py; out[o + 14] = pz; out[o + 15] = 1;
  }

  // Bodies of run r beyond the position tolerance from the baseline at frame f.
  function divergedSet(f) {
    const out = runs.map(() => null);
    if (!C) return out;
    const kb = indexAt(base, f);
    const union = new Uint8Array(N);
    let any = false;
    for (let r = 1; r < runs.length; ++r) {
      const run = runs[r], k = indexAt(run, f);
      if (k < 0 || kb < 0 || run.frames[k] !== f) continue;  // runs written with other --every: common frames only
      const set = new Uint8Array(N);
      for (let i = 0; i < N; ++i) {
        const a = (kb * N + i) * FLOATS, b = (k * N + i) * FLOATS;
        const d = Math.hypot(base.state[a] - run.state[b], base.state[a + 1] - run.state[b + 1], base.state[a + 2] - run.state[b + 2]);
        if (d > C.position_tolerance) { set[i] = 1; union[i] = 1; any = true; }
      }
      out[r] = set;
    }
    if (any && mode === 'side') out[0] = union;  // side by side: marked in every column
    return out;
  }

  // ---- state of the page ----------------------------------------------------
  let current = 0;      // index into keptFrames
  let playing = false;
  let playFrame = 0;    // fractional frame while playing
  let mode = 'overlay';
  let selected = null;  // {run, body}
  const frameOf = (k) => keptFrames[Math.max(0, Math.min(keptFrames.length - 1, k))];

  function updateScene() {
    const f = frameOf(current);
    const div = divergedSet(f);
    for (const [r, run] of runs.entries()) {
      const k = indexAt(run, f);
      const counts = { awake: 0, asleep: 0, static: 0, diverged: 0 };
      if (k >= 0 && (run.frames[run.frames.length - 1] >= f || r === 0)) {
        for (let i = 0; i < N; ++i) {
          if (run.asleepBits[k * N + i] === ABSENT) continue;
          const kind = div[r] && div[r][i] ? 'diverged' : isStatic[i] ? 'static' : run.asleepBits[k * N + i] ? 'asleep' : 'awake';
          const mesh = run.meshes[kind];
          bodyMatrix(run, k, i, mesh.instanceMatrix.array, 16 * counts[kind]++);
        }
      }
      for (const kind in counts) {
        run.meshes[kind].count = counts[kind];
        run.meshes[kind].instanceMatrix.needsUpdate = true;
      }
      const ghost = mode === 'overlay' && r > 0;
      for (const kind in run.meshes) {
        const m = run.meshes[kind].material;
        m.transparent = ghost;
        m.opacity = !ghost ? 1 : kind === 'diverged' ? 0.6 : 0.35;
        m.depthWrite = !m.transparent && run.meshes[kind].userData.shown;
        m.colorWrite = run.meshes[kind].userData.shown;
        // A ghost coinciding with the baseline's box is drawn in front of it
        // (no stripes of one and the other, z-fighting).
        m.polygonOffset = ghost;
        m.polygonOffsetFactor = ghost ? -1 : 0;
        m.polygonOffsetUnits = ghost ? -4 * r : 0;
      }
    }
    if (selected) {
      const run = runs[selected.run], k = indexAt(run, f);
      bodyMatrix(run, k, selected.body, selection.matrix.elements, 0);
      selection.matrix.elements[0] *= 1.04; selection.matrix.elements[5] *= 1.04; selection.matrix.elements[10] *= 1.04;
      selection.visible = run.asleepBits[k * N + selected.body] !== ABSENT;
    }
  }

  function resize() {
    if (!renderer) return;
    const w = container.clientWidth, h = container.clientHeight;
    renderer.setSize(w, h);
  }

  // The camera of column c of `columns` (side by side) and its viewport.
  function columnCamera(columns) {
    const w = container.clientWidth, h = container.clientHeight;
    const cw = columns > 1 ? Math.floor(w / columns) : w;
    camera.aspect = cw / Math.max(1, h);
    camera.updateProjectionMatrix();
    return [cw, h];
  }

  function render() {
    if (!renderer) return;
    const w = container.clientWidth, h = container.clientHeight;
    if (mode === 'overlay' || runs.length === 1) {
      renderer.setScissorTest(false);
      renderer.setViewport(0, 0, w, h);
      camera.aspect = w / Math.max(1, h);
      camera.updateProjectionMatrix();
      for (const run of runs) run.group.visible = true;
      renderer.render(scene, camera);
      return;
    }
    // Whole pixels per column (a fractional width would leave a seam that no
    // column clears); the canvas is cleared whole first.
    const cw = Math.floor(w / runs.length);
    camera.aspect = cw / Math.max(1, h);
    camera.updateProjectionMatrix();
    renderer.setScissorTest(false);
    renderer.setViewport(0, 0, w, h);
    renderer.clear();
    renderer.setScissorTest(true);
    for (let c = 0; c < runs.length; ++c) {
      for (const [r, run] of runs.entries()) run.group.visible = r === c;
      renderer.setViewport(c * cw, 0, cw, h);
      renderer.setScissor(c * cw, 0, cw, h);
      renderer.render(scene, camera);
    }
    renderer.setScissorTest(false);
  }

  // ---- controls -------------------------------------------------------------
  const slider = $('slider');
  slider.max = String(keptFrames.length - 1);
  $('title').textContent = D.title;
  const mib = (D.data_bytes / (1 << 20)).toFixed(2);
  $('summary').textContent = 'scene ' + S.name + ': ' + N + ' bodies, frames 0-' + keptFrames[keptFrames.length - 1] +
    (D.stride > 1 ? ' (1 frame in ' + D.stride + ' kept)' : '') + '; trajectories ' + mib + ' MiB (float32). ' +
    (C ? C.tolerance_note + ' ' + C.note : '') + (REC ? ' ' + REC.note : '');
  $('legend').innerHTML = '<span><i style="background:#4f9dff"></i>awake</span><span><i style="background:#8a7fb0"></i>asleep</span>' +
    '<span><i style="background:#6b6f78"></i>static</span>' + (C ? '<span><i style="background:#ff3b3b"></i>beyond ' +
    C.position_tolerance + ' m of ' + base.label + ' (' + C.tolerance_name + ')</span>' : '') +
    runs.map((r, i) => '<span><i style="background:' + COLORS[i % COLORS.length] + '"></i>' + r.label + '</span>').join('');
  if (runs.length < 2) $('mode-wrap').style.display = 'none';

  // Markers on the slider: where each run parts from the baseline, and the
  // first frame whose hashes differ.
  const markers = [];
  function addMarker(frame, cls, title) {
    const k = indexAt(base, frame);
    const m = document.createElement('div');
    m.className = 'marker ' + cls;
    m.style.left = (keptFrames.length > 1 ? 100 * k / (keptFrames.length - 1) : 0) + '%';
    m.dataset.frame = String(frame);
    m.title = title;
    $('markers').appendChild(m);
    markers.push({ frame: frame, kind: cls, title: title });
  }
  if (C) {
    for (let r = 1; r < runs.length; ++r)
      if (C.parted_frame[r] >= 0)
        addMarker(C.parted_frame[r], 'parted', runs[r].label + ' parts from ' + base.label + ' at frame ' + C.parted_frame[r] +
          ' (body ' + C.parted_body[r] + ')');
    if (C.first_hash_difference >= 0)
      addMarker(C.first_hash_difference, 'hash', C.note);
  }
  if (REC) {
    for (const x of REC.inputs) addMarker(x.frame, 'input', x.kind + ' before frame ' + x.frame);
    if (REC.diverged_frame >= 0)
      addMarker(REC.diverged_frame, 'diverged', 'the replay on ' + REC.engine + ' diverges from the recording at frame ' +
        REC.diverged_frame);
  }
  // "DIVERGED at frame N" over the 3D view from the first frame whose
  // replayed hash differs from the recorded one.
  function divergedOverlay() {
    const el = $('diverged');
    const on = !!REC && REC.diverged_frame >= 0 && frameOf(current) >= REC.diverged_frame;
    el.hidden = !on;
    if (on) el.textContent = 'DIVERGED at frame ' + REC.diverged_frame;
    return on;
  }

  function columnLabels() {
    const cols = $('columns');
    cols.innerHTML = '';
    if (mode !== 'side' || runs.length < 2 || isolated) return;  // isolated: the bare 3D view
    for (const r of runs) {
      const d = document.createElement('div');
      d.textContent = r.label;
      cols.appendChild(d);
    }
  }

  function fmt(v, n) { return Array.from(v).map((x) => (+x).toFixed(n === undefined ? 4 : n)).join(', '); }

  function bodyInfo() {
    const el = $('body-info');
    if (!selected) { el.textContent = 'Click a body to see its state.'; return; }
    const f = frameOf(current);
    const run = runs[selected.run], i = selected.body, k = indexAt(run, f);
    const s = (k * N + i) * FLOATS, st = run.state;
    const asleep = run.asleepBits[k * N + i];
    if (asleep === ABSENT) {
      el.textContent = run.label + ', body ' + i + ' at frame ' + run.frames[k] + ': not present (created later, or removed)';
      return;
    }
    let since = '';
    if (asleep) {
      let j = k;
      while (j > 0 && run.asleepBits[(j - 1) * N + i]) --j;
      since = j === 0 ? 'asleep since frame 0 or before' :
        (run.frames[j] - run.frames[j - 1] === 1 ? 'fell asleep at frame ' + run.frames[j] :
          'fell asleep between frames ' + (run.frames[j - 1] + 1) + ' and ' + run.frames[j]);
    }
    const lines = [
      run.label + ', body ' + i + ' at frame ' + run.frames[k],
      'state        ' + (isStatic[i] ? 'static' : asleep ? 'asleep' : 'awake'),
      'half extents ' + fmt(half.subarray(3 * i, 3 * i + 3), 3) + ' m',
      'position     ' + fmt(st.subarray(s, s + 3)) + ' m',
      'orientation  ' + fmt(st.subarray(s + 3, s + 7)) + ' (w, x, y, z)',
      'velocity     ' + fmt(st.subarray(s + 7, s + 10)) + ' m/s',
      'angular vel. ' + fmt(st.subarray(s + 10, s + 13)) + ' rad/s',
    ];
    if (since) lines.push('sleep        ' + since);
    if (C && selected.run > 0) {
      const kb = indexAt(base, f), b = (kb * N + i) * FLOATS;
      const d = Math.hypot(st[s] - base.state[b], st[s + 1] - base.state[b + 1], st[s + 2] - base.state[b + 2]);
      lines.push('from ' + base.label + ' ' + d.toExponential(3) + ' m (tolerance ' + C.position_tolerance + ' m)');
    }
    const cs = run.contacts[String(run.frames[k])];
    if (!cs) {
      lines.push('contacts     not recorded for this frame (lockstep run --contacts; compare records them for small scenes)');
    } else {
      const mine = cs.filter((c) => c[0] === i || c[1] === i);
      lines.push('contacts     ' + mine.length + (mine.length ? ' (other, point, normal, penetration):' : ''));
      for (const c of mine) {
        const other = c[0] === i ? c[1] : c[0];
        const name = other === -1 ? 'ground' : other < -1 ? 'sdf ' + (S.sdfs[-2 - other] || {}).name : 'body ' + other;
        lines.push('  ' + name + '  [' + fmt(c.slice(2, 5), 3) + ']  [' + fmt(c.slice(5, 8), 3) + ']  ' + (+c[8]).toFixed(5) + ' m');
      }
    }
    el.textContent = lines.join('\n');
  }

  function hashLine() {
    const f = frameOf(current);
    const rows = [];
    // A run's hash is compared with the first run of its engine only: runs of
    // different engines never share hashes (their numbers differ).
    for (const run of runs) {
      const ref = runs.find((o) => o.engine === run.engine);
      const h = seriesAt(run, 'hashes', f), hr = seriesAt(ref, 'hashes', f);
      const differs = ref !== run && h && hr && h !== hr;
      const same = ref !== run && h && hr && h === hr;
      rows.push('<span class="' + (differs ? 'differs' : '') + '">' + run.label + ' (' + (run.engine || '?') + '): hash ' +
        (h || 'n/a') + (differs ? ' (differs from ' + ref.label + ')' : same ? ' (= ' + ref.label + ')' : '') + '</span>');
    }
    $('hashes').innerHTML = rows.join('<br>') + (C && C.note ? '<br>' + C.note : '') + (REC ? '<br>' + REC.note.replace(/[<>&]/g, (c) => ({ '<': '&lt;', '>': '&gt;', '&': '&amp;' })[c]) : '');
  }

  function status() {
    let boxes = 0;
    for (const run of runs) for (const kind in run.meshes) boxes += run.meshes[kind].count;
    const st = { ready: true, frame: frameOf(current), index: current, boxes: boxes, bodies: N, runs: runs.length,
      markers: markers, errors: window.lockstepErrors.slice(), bench: benchResult, setup_ms: setupMs,
      page_ready_ms: started + setupMs, webgl: !!renderer, mode: mode,
      tolerance: C ? { position: C.position_tolerance, orientation: C.orientation_tolerance, name: C.tolerance_name } : null,
      recording: REC ? { inputs: REC.inputs.length, diverged_frame: REC.diverged_frame, overlay: !$('diverged').hidden } : null };
    if (isolated) st.footprints = footprints();
    const shown = {};
    for (const [r, run] of runs.entries())
      for (const kind in run.meshes) if (run.meshes[kind].userData.shown) shown[r + ':' + kind] = run.meshes[kind].count;
    st.drawn = shown;
    $('lockstep-status').textContent = JSON.stringify(st);
    return st;
  }

  // The boxes drawn when only one group is (#only, #run): each box's eight
  // corners projected to pixels of the 3D view's canvas (from its top left),
  // with the canvas's place on the page. The browser test compares them with
  // the screenshot's pixels: what is drawn must cover them, and nothing else.
  function footprints() {
    const f = frameOf(current), out = [];
    const columns = mode === 'side' && runs.length > 1 ? runs.length : 1;
    const [cw, ch] = columnCamera(columns);
    camera.updateMatrixWorld();
    const m = new Array(16), v = new THREE.Vector3();
    const div = divergedSet(f);
    for (const [r, run] of runs.entries()) {
      if (onlyRun !== null && onlyRun !== r) continue;
      const k = indexAt(run, f);
      if (k < 0) continue;
      const x0 = columns > 1 ? r * cw : 0;
      for (let i = 0; i < N; ++i) {
        if (run.asleepBits[k * N + i] === ABSENT) continue;
        const kind = div[r] && div[r][i] ? 'diverged' : isStatic[i] ? 'static' : run.asleepBits[k * N + i] ? 'asleep' : 'awake';
        if (onlyKind !== null && onlyKind !== kind) continue;
        bodyMatrix(run, k, i, m, 0);
        const corners = [];
        for (const sx of [-0.5, 0.5]) for (const sy of [-0.5, 0.5]) for (const sz of [-0.5, 0.5]) {
          v.set(m[0] * sx + m[4] * sy + m[8] * sz + m[12], m[1] * sx + m[5] * sy + m[9] * sz + m[13],
            m[2] * sx + m[6] * sy + m[10] * sz + m[14]).project(camera);
          corners.push([+(x0 + (v.x + 1) / 2 * cw).toFixed(1), +((1 - v.y) / 2 * ch).toFixed(1)]);
        }
        out.push({ run: r, body: i, kind: kind, corners: corners });
      }
    }
    const rect = (renderer ? renderer.domElement : container).getBoundingClientRect();
    return { canvas: [rect.left, rect.top, rect.width, rect.height], boxes: out };
  }

  let charts = [];
  let benchResult = null, setupMs = null;
  function setFrameIndex(k) {
    current = Math.max(0, Math.min(keptFrames.length - 1, k | 0));
    slider.value = String(current);
    const f = frameOf(current);
    $('frame-label').textContent = 'frame ' + f + ' / ' + keptFrames[keptFrames.length - 1] +
      '  (t = ' + (f * S.dt).toFixed(3) + ' s)';
    updateScene();
    bodyInfo();
    hashLine();
    divergedOverlay();
    for (const c of charts) c.draw();
    render();
    status();
  }
  const setFrame = (f) => setFrameIndex(indexAt(base, f));

  slider.addEventListener('input', () => { setFrameIndex(+slider.value); playFrame = frameOf(current); });
  $('play').addEventListener('click', () => togglePlay());
  $('back').addEventListener('click', () => setFrameIndex(current - 1));
  $('forward').addEventListener('click', () => setFrameIndex(current + 1));
  $('mode').addEventListener('change', () => { mode = $('mode').value; columnLabels(); setFrameIndex(current); });
  function togglePlay() {
    playing = !playing;
    if (playing && current >= keptFrames.length - 1) setFrameIndex(0);
    playFrame = frameOf(current);
    $('play').innerHTML = playing ? '&#10074;&#10074;' : '&#9654;';
  }
  window.addEventListener('keydown', (e) => {
    if (e.target && e.target.tagName === 'SELECT') return;
    const step = e.shiftKey ? 10 : 1;
    if (e.key === ' ') { togglePlay(); e.preventDefault(); }
    else if (e.key === 'ArrowRight') { setFrameIndex(current + step); e.preventDefault(); }
    else if (e.key === 'ArrowLeft') { setFrameIndex(current - step); e.preventDefault(); }
    else if (e.key === 'Home') setFrameIndex(0);
    else if (e.key === 'End') setFrameIndex(keptFrames.length - 1);
  });
  window.addEventListener('resize', () => { resize(); render(); });
  if (controls) controls.addEventListener('change', () => render());

  // Picking: the nearest box the ray through the pixel enters (ray against
  // each body's oriented box, in the body's frame).
  let downAt = null;
  if (renderer) {
    renderer.domElement.addEventListener('pointerdown', (e) => { downAt = [e.clientX, e.clientY]; });
    renderer.domElement.addEventListener('pointerup', (e) => {
      if (!downAt || Math.hypot(e.clientX - downAt[0], e.clientY - downAt[1]) > 4) return;
      const rect = renderer.domElement.getBoundingClientRect();
      pickAt((e.clientX - rect.left) / rect.width, (e.clientY - rect.top) / rect.height);
    });
  }
  // x, y: the point on the 3D view, 0..1 from its top left corner.
  function pickAt(xView, yView) {
    let x = xView, r = 0;
    if (mode === 'side' && runs.length > 1) { r = Math.min(runs.length - 1, Math.floor(x * runs.length)); x = x * runs.length - r; }
    columnCamera(mode === 'side' && runs.length > 1 ? runs.length : 1);
    const ndc = new THREE.Vector2(2 * x - 1, 1 - 2 * yView);
    const ray = new THREE.Raycaster();
    ray.setFromCamera(ndc, camera);
    const o = ray.ray.origin, d = ray.ray.direction, run = runs[r], k = indexAt(run, frameOf(current));
    let best = Infinity, hit = -1;
    const q = new THREE.Quaternion(), lo3 = new THREE.Vector3(), ld3 = new THREE.Vector3();
    for (let i = 0; i < N; ++i) {
      if (run.asleepBits[k * N + i] === ABSENT) continue;
      const s = (k * N + i) * FLOATS, st = run.state;
      q.set(st[s + 4], st[s + 5], st[s + 6], st[s + 3]).normalize().inverse();
      lo3.set(o.x - st[s], o.y - st[s + 1], o.z - st[s + 2]).applyQuaternion(q);
      ld3.copy(d).applyQuaternion(q);
      let t0 = -Infinity, t1 = Infinity;
      for (let a = 0; a < 3; ++a) {
        const h = half[3 * i + a], oa = lo3.getComponent(a), da = ld3.getComponent(a);
        if (Math.abs(da) < 1e-12) { if (Math.abs(oa) > h) { t0 = Infinity; break; } continue; }
        let ta = (-h - oa) / da, tb = (h - oa) / da;
        if (ta > tb) [ta, tb] = [tb, ta];
        t0 = Math.max(t0, ta); t1 = Math.min(t1, tb);
      }
      if (t0 <= t1 && t1 > 0 && t0 < best) { best = Math.max(0, t0); hit = i; }
    }
    selected = hit >= 0 ? { run: r, body: hit } : null;
    selection.visible = !!selected;
    setFrameIndex(current);
    return selected;
  }

  // ---- charts ---------------------------------------------------------------
  const cursor = {
    id: 'lockstepCursor',
    afterDraw(chart) {
      const x = chart.scales.x, area = chart.chartArea, ctx = chart.ctx;
      ctx.save();
      ctx.strokeStyle = '#ffffff';
      ctx.lineWidth = 1;
      const px = x.getPixelForValue(frameOf(current));
      ctx.beginPath(); ctx.moveTo(px, area.top); ctx.lineTo(px, area.bottom); ctx.stroke();
      ctx.strokeStyle = '#ff4d4d';
      ctx.setLineDash([4, 3]);
      for (const m of markers) {
        if (m.kind !== 'parted') continue;
        const mx = x.getPixelForValue(m.frame);
        ctx.beginPath(); ctx.moveTo(mx, area.top); ctx.lineTo(mx, area.bottom); ctx.stroke();
      }
      ctx.restore();
    },
  };
  Chart.defaults.color = '#bbc';
  Chart.defaults.borderColor = '#3a3d44';
  function series(run, name) {
    const out = [], values = run[name], every = run.series_every || 1;
    if (!values) return out;
    for (let k = 0; k < values.length; ++k) if (values[k] !== null && values[k] !== undefined) out.push({ x: k * every, y: values[k] });
    return out;
  }
  function chart(id, title, yTitle, datasets, extra) {
    if (!datasets.some((d) => d.data.length)) {
      const p = document.createElement('div');
      p.textContent = title + ': not recorded';
      $(id).replaceWith(p);
      return;
    }
    const c = new Chart($(id).getContext('2d'), {
      type: 'line',
      data: { datasets: datasets },
      options: Object.assign({
        animation: false, parsing: false, normalized: true, responsive: true, maintainAspectRatio: false,
        elements: { point: { radius: 0 }, line: { borderWidth: 1.5 } },
        scales: { x: { type: 'linear', title: { display: true, text: 'frame' } }, y: { title: { display: true, text: yTitle } } },
        plugins: { title: { display: true, text: title }, legend: { labels: { boxWidth: 10 } }, decimation: { enabled: true } },
        onClick(e, els, ch) {
          const f = ch.scales.x.getValueForPixel(e.x);
          if (isFinite(f)) { setFrame(Math.round(f)); playFrame = frameOf(current); }
        },
      }, extra || {}),
      plugins: [cursor],
    });
    charts.push(c);
  }
  const ds = (r, data) => ({ label: runs[r].label, data: data, borderColor: COLORS[r % COLORS.length], backgroundColor: COLORS[r % COLORS.length] });
  chart('chart-energy', 'energy (kinetic + potential)', 'J', runs.map((r, i) => ds(i, series(r, 'energy'))));
  if (C) {
    // On a log scale (what lies below the tolerance shows too); a run that
    // matches the baseline bit for bit (0 m) is drawn at FLOOR.
    const FLOOR = 1e-9;
    const sets = [];
    for (let r = 1; r < runs.length; ++r) {
      const pts = [];
      C.divergence[r].forEach((v, k) => { if (v !== null && v !== undefined) pts.push({ x: base.frames[k], y: Math.max(FLOOR, v) }); });
      sets.push(ds(r, pts));
    }
    sets.push({ label: C.tolerance_name + ' ' + C.position_tolerance + ' m',
      data: [{ x: 0, y: C.position_tolerance }, { x: keptFrames[keptFrames.length - 1], y: C.position_tolerance }],
      borderColor: '#ff4d4d', borderDash: [4, 3], backgroundColor: '#ff4d4d' });
    chart('chart-divergence', 'divergence from ' + base.label + ' (max over bodies; log scale, 0 drawn at 1e-9 m)', 'm', sets,
      { scales: { x: { type: 'linear', title: { display: true, text: 'frame' } },
                  y: { type: 'logarithmic', min: FLOOR, title: { display: true, text: 'm (log)' },
                       ticks: { callback: (v) => { const e = Math.log10(v); return Math.abs(e - Math.round(e)) < 1e-6 ? '1e' + Math.round(e) : ''; } } } } });
  } else {
    $('chart-divergence-wrap').style.display = 'none';
  }
  chart('chart-sleep', 'sleep timeline: bodies asleep', 'bodies', runs.map((r, i) => ds(i, series(r, 'asleep_count'))));
  chart('chart-contacts', 'contacts per frame', 'contacts', runs.map((r, i) => ds(i, series(r, 'contact_count'))));

  // ---- playback ---------------------------------------------------------------
  let last = null, ticks = 0;
  function tick(now) {
    if (playing && last !== null) {
      const speed = +$('speed').value;
      playFrame += speed * (now - last) / 1000 / S.dt;
      const k = indexAt(base, Math.floor(playFrame));
      if (k !== current) setFrameIndex(k);
      if (playFrame >= keptFrames[keptFrames.length - 1]) { playing = true; togglePlay(); }
    }
    last = now;
    if (++ticks % 30 === 0) status();  // errors raised after load show too
    requestAnimationFrame(tick);
  }

  // #frame=N, #mode=side, #select=RUN,BODY, #pick=X,Y, #play in the address pick the first view
  // (#only=GROUP, #run=R: above).
  if (params.get('mode') === 'side' && runs.length > 1) { mode = 'side'; $('mode').value = 'side'; }
  if (params.has('select')) {
    const [r, b] = params.get('select').split(',').map(Number);
    if (runs[r] && b >= 0 && b < N) selected = { run: r, body: b };
  }
  columnLabels();
  resize();
  setFrame(params.has('frame') ? +params.get('frame') : 0);
  if (params.has('play')) togglePlay();
  if (params.has('pick')) pickAt(...params.get('pick').split(',').map(Number));  // #pick=X,Y: a click there
  // #bench=N: time N frame steps (scene update alone, and update + draw),
  // reported in the status as ms per frame.
  if (params.has('bench')) {
    const n = Math.max(1, +params.get('bench'));
    let t0 = performance.now();
    for (let i = 0; i < n; ++i) { current = i % keptFrames.length; updateScene(); }
    const update = (performance.now() - t0) / n;
    t0 = performance.now();
    for (let i = 0; i < n; ++i) { current = i % keptFrames.length; updateScene(); render(); }
    if (renderer) renderer.getContext().finish();
    const both = (performance.now() - t0) / n;
    benchResult = { frames: n, update_ms: update, update_and_draw_ms: both };
    setFrameIndex(0);
  }
  setupMs = performance.now() - started;
  status();
  requestAnimationFrame(tick);

  window.lockstepView = {
    setFrame: setFrame,
    setFrameIndex: setFrameIndex,
    status: status,
    markers: markers,
    pick: pickAt,
    select: (run, body) => { selected = { run: run, body: body }; setFrameIndex(current); return $('body-info').textContent; },
  };
})();
