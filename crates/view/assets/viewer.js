// stride view: animates the gait cycles embedded in the page (JSON in #stride-data) with
// three.js (the global THREE, embedded before this script). Ground frame as in OpenSim:
// x forward, y up, z to the right; metres, newtons, seconds.
// Page options after `#` in the address: play=0 (start paused), t=0.25 (start at this
// fraction of the cycle), model=0 (hide the model: an empty stage), view=side|front|top|oblique,
// case=i (the study case shown first, 0-based).
(function () {
  'use strict';
  var data = JSON.parse(document.getElementById('stride-data').textContent);
  var params = new URLSearchParams(location.hash.slice(1));
  var $ = function (id) { return document.getElementById(id); };
  var model = data.model;
  var NB = model.bodies.length;
  var NM = model.muscles.length;
  var BODY_WEIGHT = Math.max(model.mass, 1) * 9.81;
  var GRF_METRES_PER_BW = 0.9;
  var MUSCLE_RADIUS = 0.0045;

  // ---- decoding of the embedded arrays (see stride_view::encode) ----
  function bytes(b64) {
    var bin = atob(b64);
    var out = new Uint8Array(bin.length);
    for (var i = 0; i < bin.length; i++) out[i] = bin.charCodeAt(i);
    return out;
  }
  function dequantise(q) {
    var b = bytes(q.data);
    var v = new DataView(b.buffer);
    var out = new Float32Array(q.len);
    for (var i = 0; i < q.len; i++) out[i] = q.offset + q.step * v.getInt16(2 * i, true);
    return out;
  }
  function decoded(c) {
    if (!c.frames) {
      c.frames = {
        n: c.time.length,
        duration: c.time[c.time.length - 1],
        origins: dequantise(c.origins),
        rotations: dequantise(c.rotations),
        muscles: dequantise(c.muscles),
        act: bytes(c.activations),
        grf: c.grf ? Float32Array.from(c.grf) : null
      };
    }
    return c.frames;
  }

  // muscle path points: offset of each muscle's first point within a frame
  var pointStart = [];
  var nPoints = 0;
  var nMuscleSegments = 0;
  model.muscles.forEach(function (m) {
    pointStart.push(nPoints);
    nPoints += m.points;
    nMuscleSegments += Math.max(m.points - 1, 0);
  });

  // ---- scene ----
  var container = $('view3d');
  var renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
  renderer.shadowMap.enabled = true;
  renderer.shadowMap.type = THREE.PCFShadowMap;
  renderer.toneMapping = THREE.ACESFilmicToneMapping;
  container.appendChild(renderer.domElement);
  var scene = new THREE.Scene();
  var sky = new THREE.Color(0xe9eef4);
  scene.background = sky;
  scene.fog = new THREE.Fog(sky, 10, 32);
  var camera = new THREE.PerspectiveCamera(32, 1, 0.05, 120);
  var controls = new THREE.OrbitControls(camera, renderer.domElement);
  controls.enableDamping = true;
  controls.dampingFactor = 0.12;
  controls.maxPolarAngle = Math.PI * 0.499;
  controls.minDistance = 0.5;
  controls.maxDistance = 25;

  scene.add(new THREE.HemisphereLight(0xffffff, 0x9a948a, 1.9));
  var sun = new THREE.DirectionalLight(0xffffff, 2.4);
  sun.castShadow = true;
  sun.shadow.mapSize.set(2048, 2048);
  var sc = sun.shadow.camera;
  sc.left = -2.5; sc.right = 2.5; sc.top = 2.5; sc.bottom = -2.5; sc.near = 0.5; sc.far = 20;
  sun.shadow.bias = -0.0005;
  scene.add(sun);
  scene.add(sun.target);

  var ground = new THREE.Mesh(
    new THREE.PlaneGeometry(80, 80),
    new THREE.MeshStandardMaterial({ color: 0xcfd6de, roughness: 1 })
  );
  ground.rotation.x = -Math.PI / 2;
  ground.receiveShadow = true;
  scene.add(ground);
  var grid = new THREE.GridHelper(80, 160, 0x66717f, 0x97a2ae);
  grid.position.y = 0.002;
  scene.add(grid);

  var root = new THREE.Group();
  scene.add(root);
  var unitCylinder = new THREE.CylinderGeometry(1, 1, 1, 20, 1);
  var unitSphere = new THREE.SphereGeometry(1, 28, 18);
  var boneMat = new THREE.MeshStandardMaterial({ color: 0xefe6d6, roughness: 0.5 });
  var jointMat = new THREE.MeshStandardMaterial({ color: 0xaab4c2, roughness: 0.45 });
  var contactMat = new THREE.MeshStandardMaterial({
    color: 0x7f93aa, roughness: 0.6, transparent: true, opacity: 0.6
  });
  function solid(geometry, material) {
    var m = new THREE.Mesh(geometry, material);
    m.castShadow = true;
    return m;
  }

  var UP = new THREE.Vector3(0, 1, 0);
  var va = new THREE.Vector3(), vb = new THREE.Vector3(), vd = new THREE.Vector3();
  var tq = new THREE.Quaternion(), ts = new THREE.Vector3(), tm = new THREE.Matrix4();
  // a unit cylinder (axis y) placed between points a and b with radius r
  function segmentTransform(a, b, r, position, quaternion, scale) {
    vd.subVectors(b, a);
    var len = vd.length();
    position.addVectors(a, b).multiplyScalar(0.5);
    if (len > 1e-9) quaternion.setFromUnitVectors(UP, vd.multiplyScalar(1 / len));
    scale.set(r, Math.max(len, 1e-6), r);
  }
  function placeSegment(mesh, a, b, r) {
    segmentTransform(a, b, r, mesh.position, mesh.quaternion, mesh.scale);
  }

  // bodies: a frame per body, posed every frame; joint ball at the origin, tip segment for
  // bodies without children, contact spheres
  var bodyFrames = model.bodies.map(function (b) {
    var g = new THREE.Group();
    g.matrixAutoUpdate = false;
    var ball = solid(unitSphere, jointMat);
    ball.scale.setScalar(b.radius * 1.3);
    g.add(ball);
    if (b.tip) {
      var tip = solid(unitCylinder, boneMat);
      placeSegment(tip, new THREE.Vector3(0, 0, 0), new THREE.Vector3().fromArray(b.tip), b.radius);
      g.add(tip);
      var cap = solid(unitSphere, boneMat);
      cap.scale.setScalar(b.radius);
      cap.position.fromArray(b.tip);
      g.add(cap);
    }
    root.add(g);
    return g;
  });
  model.spheres.forEach(function (s) {
    var m = solid(unitSphere, contactMat);
    m.position.fromArray(s.center);
    m.scale.setScalar(s.radius);
    bodyFrames[s.body].add(m);
  });
  // bones: from each body's parent origin to its origin (its joint centre)
  var bones = [];
  model.bodies.forEach(function (b, i) {
    if (b.parent === null || b.parent === undefined) return;
    var mesh = solid(unitCylinder, boneMat);
    root.add(mesh);
    bones.push({ mesh: mesh, from: b.parent, to: i, radius: model.bodies[b.parent].radius });
  });
  // muscles: one instanced cylinder per path segment, coloured by activation
  var muscleMat = new THREE.MeshStandardMaterial({ color: 0xffffff, roughness: 0.55 });
  var muscleMesh = new THREE.InstancedMesh(new THREE.CylinderGeometry(1, 1, 1, 8, 1), muscleMat, Math.max(nMuscleSegments, 1));
  muscleMesh.count = nMuscleSegments;
  muscleMesh.castShadow = true;
  muscleMesh.frustumCulled = false;
  root.add(muscleMesh);
  // ground reaction forces: shaft and head per foot (right, left)
  var grfColors = [0x1f77b4, 0xe8710a];
  var arrows = grfColors.map(function (c) {
    var mat = new THREE.MeshStandardMaterial({ color: c, roughness: 0.4 });
    var shaft = solid(unitCylinder, mat);
    var head = solid(new THREE.ConeGeometry(1, 1, 20), mat);
    root.add(shaft);
    root.add(head);
    return { shaft: shaft, head: head };
  });

  // activation colour: slate (0) → amber (0.5) → red (1); unknown: grey
  var actStops = [new THREE.Color(0x5b6f93), new THREE.Color(0xe8a33a), new THREE.Color(0xe3261b)];
  var unknownColor = new THREE.Color(0x9a9a9a);
  var tc = new THREE.Color();
  function activationColor(a) {
    if (a < 0) return unknownColor;
    var x = Math.min(Math.max(a, 0), 1) * 2;
    var k = Math.min(Math.floor(x), 1);
    return tc.copy(actStops[k]).lerp(actStops[k + 1], x - k);
  }

  // ---- state ----
  var cases = data.cases;
  var current = null;
  var phase = Math.min(Math.max(parseFloat(params.get('t')) || 0, 0), 1) % 1;
  var playing = params.get('play') !== '0';
  var speed = 1;
  var follow = true;
  var lastRootX = null;
  if (params.get('model') === '0') root.visible = false;

  // value of component k of item `item` (of `width` values per item, `items` per frame) at
  // the current fractional frame
  var F = { i0: 0, i1: 0, w: 0 };
  function at(arr, perFrame, k) {
    return arr[F.i0 * perFrame + k] * (1 - F.w) + arr[F.i1 * perFrame + k] * F.w;
  }

  function pose() {
    var f = decoded(current);
    var x = phase * (f.n - 1);
    F.i0 = Math.floor(x);
    F.i1 = Math.min(F.i0 + 1, f.n - 1);
    F.w = x - F.i0;
    for (var b = 0; b < NB; b++) {
      var o = 3 * b, r = 9 * b, nr = 9 * NB, no = 3 * NB;
      bodyFrames[b].matrix.set(
        at(f.rotations, nr, r), at(f.rotations, nr, r + 1), at(f.rotations, nr, r + 2), at(f.origins, no, o),
        at(f.rotations, nr, r + 3), at(f.rotations, nr, r + 4), at(f.rotations, nr, r + 5), at(f.origins, no, o + 1),
        at(f.rotations, nr, r + 6), at(f.rotations, nr, r + 7), at(f.rotations, nr, r + 8), at(f.origins, no, o + 2),
        0, 0, 0, 1
      );
      bodyFrames[b].matrixWorldNeedsUpdate = true;
    }
    bones.forEach(function (bone) {
      va.set(at(f.origins, 3 * NB, 3 * bone.from), at(f.origins, 3 * NB, 3 * bone.from + 1), at(f.origins, 3 * NB, 3 * bone.from + 2));
      vb.set(at(f.origins, 3 * NB, 3 * bone.to), at(f.origins, 3 * NB, 3 * bone.to + 1), at(f.origins, 3 * NB, 3 * bone.to + 2));
      placeSegment(bone.mesh, va, vb, bone.radius);
    });
    poseMuscles(f);
    poseForces(f);
  }

  var tp = new THREE.Vector3();
  function poseMuscles(f) {
    if (!muscleMesh.visible) return;
    var perFrame = 3 * nPoints;
    var seg = 0;
    for (var m = 0; m < NM; m++) {
      var a0 = f.act[F.i0 * NM + m], a1 = f.act[F.i1 * NM + m];
      var a = a0 === 255 || a1 === 255 ? -1 : (a0 * (1 - F.w) + a1 * F.w) / 254;
      var color = activationColor(a);
      for (var k = 0; k < model.muscles[m].points; k++) {
        var p = 3 * (pointStart[m] + k);
        vb.set(at(f.muscles, perFrame, p), at(f.muscles, perFrame, p + 1), at(f.muscles, perFrame, p + 2));
        if (k > 0) {
          segmentTransform(va, vb, MUSCLE_RADIUS, tp, tq, ts);
          tm.compose(tp, tq, ts);
          muscleMesh.setMatrixAt(seg, tm);
          muscleMesh.setColorAt(seg, color);
          seg++;
        }
        va.copy(vb);
      }
    }
    muscleMesh.instanceMatrix.needsUpdate = true;
    if (muscleMesh.instanceColor) muscleMesh.instanceColor.needsUpdate = true;
  }

  function poseForces(f) {
    arrows.forEach(function (arrow, s) {
      var visible = !!f.grf && $('show-grf').checked;
      if (visible) {
        vd.set(at(f.grf, 12, 6 * s), at(f.grf, 12, 6 * s + 1), at(f.grf, 12, 6 * s + 2));
        va.set(at(f.grf, 12, 6 * s + 3), at(f.grf, 12, 6 * s + 4), at(f.grf, 12, 6 * s + 5));
        var mag = vd.length();
        visible = mag > 0.01 * BODY_WEIGHT;
        if (visible) {
          var len = (mag / BODY_WEIGHT) * GRF_METRES_PER_BW;
          var headLen = Math.min(0.08, 0.5 * len);
          vd.multiplyScalar(1 / mag);
          vb.copy(va).addScaledVector(vd, len - headLen);
          placeSegment(arrow.shaft, va, vb, 0.009);
          arrow.head.position.copy(vb).addScaledVector(vd, headLen / 2);
          arrow.head.quaternion.setFromUnitVectors(UP, vd);
          arrow.head.scale.set(0.025, headLen, 0.025);
        }
      }
      arrow.shaft.visible = visible;
      arrow.head.visible = visible;
    });
  }

  // ---- camera ----
  function rootPosition() {
    var f = decoded(current);
    return new THREE.Vector3(at(f.origins, 3 * NB, 0), at(f.origins, 3 * NB, 1), at(f.origins, 3 * NB, 2));
  }
  var VIEWS = {
    side: [0, 0.1, 3.3],
    front: [3.3, 0.1, 0],
    top: [0, 3.6, 0.01],
    oblique: [2.1, 0.75, 2.6]
  };
  function setView(name) {
    var target = rootPosition();
    target.y *= 0.68; // a little below the pelvis: the whole body above the control bar
    controls.target.copy(target);
    camera.position.copy(target).add(new THREE.Vector3().fromArray(VIEWS[name] || VIEWS.oblique));
    camera.lookAt(target);
    controls.update();
    lastRootX = target.x;
    document.querySelectorAll('button.cam').forEach(function (b) {
      b.classList.toggle('active', b.dataset.view === name);
    });
  }
  function followRoot() {
    var x = rootPosition().x;
    if (follow && lastRootX !== null) {
      var dx = x - lastRootX;
      camera.position.x += dx;
      controls.target.x += dx;
    }
    lastRootX = x;
    sun.target.position.copy(controls.target);
    sun.position.copy(controls.target).add(new THREE.Vector3(2.5, 6, 3.5));
  }

  // ---- curves ----
  var GRF_CURVES = [
    { key: 'grf:1', label: 'vertical ground reaction force [% body weight]' },
    { key: 'grf:0', label: 'fore-aft ground reaction force [% body weight]' },
    { key: 'grf:2', label: 'mediolateral ground reaction force [% body weight]' }
  ];
  function curveOptions(c) {
    var names = {};
    c.curves.forEach(function (cv) { names[cv.name] = cv; });
    var opts = [];
    c.curves.forEach(function (cv) {
      if (/_l$/.test(cv.name) && names[cv.name.replace(/_l$/, '_r')]) return;
      var paired = /_r$/.test(cv.name) && names[cv.name.replace(/_r$/, '_l')];
      opts.push({ key: 'q:' + cv.name, label: (paired ? cv.name.replace(/_r$/, '') + ' (right, left)' : cv.name) + ' [' + cv.unit + ']' });
    });
    if (c.grf) opts = opts.concat(GRF_CURVES);
    return opts;
  }
  // the series of a curve key: [right (or only), left (or null)]
  function series(c, key) {
    var n = c.time.length;
    if (key.indexOf('grf:') === 0) {
      var k = +key.slice(4);
      var out = [[], []];
      for (var i = 0; i < n; i++) {
        out[0].push(100 * c.grf[12 * i + k] / BODY_WEIGHT);
        out[1].push(100 * c.grf[12 * i + 6 + k] / BODY_WEIGHT);
      }
      return out;
    }
    var name = key.slice(2);
    var find = function (nm) {
      for (var j = 0; j < c.curves.length; j++) if (c.curves[j].name === nm) return c.curves[j].values;
      return null;
    };
    return [find(name), /_r$/.test(name) ? find(name.replace(/_r$/, '_l')) : null];
  }
  var DEFAULT_PLOTS = ['q:hip_flexion_r', 'q:knee_angle_r', 'q:ankle_angle_r', 'grf:1'];
  var plots = [];
  function buildPlots() {
    var box = $('plots');
    var opts = curveOptions(current);
    var keys = opts.map(function (o) { return o.key; });
    var chosen = plots.map(function (p) { return p.key; });
    box.textContent = '';
    plots = [];
    for (var i = 0; i < 4; i++) {
      var key = chosen[i] && keys.indexOf(chosen[i]) >= 0 ? chosen[i]
        : keys.indexOf(DEFAULT_PLOTS[i]) >= 0 ? DEFAULT_PLOTS[i] : keys[Math.min(i, keys.length - 1)];
      var div = document.createElement('div');
      div.className = 'plot';
      var sel = document.createElement('select');
      opts.forEach(function (o) {
        var op = document.createElement('option');
        op.value = o.key;
        op.textContent = o.label;
        sel.appendChild(op);
      });
      sel.value = key;
      var canvas = document.createElement('canvas');
      div.appendChild(sel);
      div.appendChild(canvas);
      box.appendChild(div);
      var plot = { key: key, canvas: canvas, base: null };
      sel.addEventListener('change', (function (p, s) {
        return function () { p.key = s.value; p.base = null; };
      })(plot, sel));
      plots.push(plot);
    }
  }
  var PAD = { l: 38, r: 14, t: 8, b: 18 };
  function drawBase(p) {
    var dpr = window.devicePixelRatio || 1;
    var w = Math.max(p.canvas.clientWidth, 100), h = Math.max(p.canvas.clientHeight, 60);
    p.canvas.width = Math.round(w * dpr);
    p.canvas.height = Math.round(h * dpr);
    var s = series(current, p.key);
    var all = s[0].concat(s[1] || []);
    var lo = Math.min.apply(null, all), hi = Math.max.apply(null, all);
    if (!(hi > lo)) { lo -= 1; hi += 1; }
    var padY = 0.06 * (hi - lo);
    lo -= padY; hi += padY;
    var base = document.createElement('canvas');
    base.width = p.canvas.width;
    base.height = p.canvas.height;
    var g = base.getContext('2d');
    g.scale(dpr, dpr);
    var X = function (u) { return PAD.l + u * (w - PAD.l - PAD.r); };
    var Y = function (v) { return PAD.t + (hi - v) / (hi - lo) * (h - PAD.t - PAD.b); };
    g.fillStyle = '#fbfcfd';
    g.fillRect(PAD.l, PAD.t, w - PAD.l - PAD.r, h - PAD.t - PAD.b);
    g.strokeStyle = '#d9dde3';
    g.lineWidth = 1;
    g.strokeRect(PAD.l, PAD.t, w - PAD.l - PAD.r, h - PAD.t - PAD.b);
    g.fillStyle = '#667085';
    g.font = '10px system-ui, sans-serif';
    g.textAlign = 'right';
    g.textBaseline = 'middle';
    [lo + padY, hi - padY].forEach(function (v) {
      g.fillText(v.toPrecision(3).replace(/\.?0+$/, ''), PAD.l - 4, Y(v));
    });
    if (lo < 0 && hi > 0) {
      g.strokeStyle = '#c3cad3';
      g.beginPath(); g.moveTo(X(0), Y(0)); g.lineTo(X(1), Y(0)); g.stroke();
    }
    g.textAlign = 'center';
    g.textBaseline = 'top';
    [0, 50, 100].forEach(function (pct) { g.fillText(pct + ' %', X(pct / 100), h - PAD.b + 4); });
    var n = current.time.length;
    [[s[0], '#1f77b4'], [s[1], '#e8710a']].forEach(function (sc) {
      if (!sc[0]) return;
      g.strokeStyle = sc[1];
      g.lineWidth = 1.7;
      g.beginPath();
      sc[0].forEach(function (v, i) {
        var px = X(i / (n - 1)), py = Y(v);
        if (i) g.lineTo(px, py); else g.moveTo(px, py);
      });
      g.stroke();
    });
    p.base = { canvas: base, X: X, w: w, h: h, dpr: dpr };
  }
  function drawPlots() {
    plots.forEach(function (p) {
      if (!p.base || p.base.w !== p.canvas.clientWidth) drawBase(p);
      var g = p.canvas.getContext('2d');
      g.setTransform(1, 0, 0, 1, 0, 0);
      g.clearRect(0, 0, p.canvas.width, p.canvas.height);
      g.drawImage(p.base.canvas, 0, 0);
      g.scale(p.base.dpr, p.base.dpr);
      var x = p.base.X(phase);
      g.strokeStyle = '#1d2430';
      g.lineWidth = 1.2;
      g.beginPath(); g.moveTo(x, PAD.t); g.lineTo(x, p.base.h - PAD.b); g.stroke();
    });
  }

  // ---- side panel ----
  function prettyName(k) { return k.replace(/_/g, ' '); }
  function showOutcomes(c) {
    var t = $('outcomes');
    t.textContent = '';
    if (!c.outcomes.length) {
      t.innerHTML = '<tr><td>no summary.json</td></tr>';
      return;
    }
    c.outcomes.forEach(function (kv) {
      var tr = document.createElement('tr');
      var a = document.createElement('td'), b = document.createElement('td');
      a.textContent = prettyName(kv[0]);
      b.textContent = String(kv[1]);
      tr.appendChild(a); tr.appendChild(b);
      t.appendChild(tr);
    });
  }
  function setCase(i) {
    current = cases[i];
    decoded(current);
    $('case-title').textContent = current.name + (current.grf ? '' : ' (no grf.mot: no forces)');
    showOutcomes(current);
    buildPlots();
    lastRootX = null;
    pose();
    followRoot();
  }
  function buildCaseList() {
    if (cases.length < 2) return;
    $('cases-box').hidden = false;
    var sel = $('cases');
    cases.forEach(function (c, i) {
      var op = document.createElement('option');
      op.value = i;
      op.textContent = c.name;
      sel.appendChild(op);
    });
    sel.value = '0';
    sel.addEventListener('change', function () {
      setCase(+sel.value);
      setView(activeView);
    });
    $('case-filter').addEventListener('input', function () {
      var f = this.value.toLowerCase();
      Array.prototype.forEach.call(sel.options, function (op) {
        op.hidden = f !== '' && op.textContent.toLowerCase().indexOf(f) < 0;
      });
    });
  }
  function buildFigures() {
    if (!data.figures.length) return;
    $('figures-box').hidden = false;
    var list = $('figure-list');
    data.figures.forEach(function (fg) {
      var fig = document.createElement('figure');
      var img = document.createElement('img');
      img.src = fg.uri;
      img.alt = fg.name;
      var cap = document.createElement('figcaption');
      cap.textContent = prettyName(fg.name.replace(/^figure_/, ''));
      fig.appendChild(img);
      fig.appendChild(cap);
      fig.addEventListener('click', function () {
        $('figure-big').src = fg.uri;
        $('figure-overlay').hidden = false;
      });
      list.appendChild(fig);
    });
    $('figure-overlay').addEventListener('click', function () { this.hidden = true; });
  }

  // ---- controls ----
  var activeView = params.get('view') || 'oblique';
  function setPlaying(p) {
    playing = p;
    $('play').innerHTML = p ? '&#10074;&#10074;' : '&#9654;';
  }
  $('play').addEventListener('click', function () { setPlaying(!playing); });
  var slider = $('slider');
  slider.addEventListener('input', function () {
    setPlaying(false);
    phase = Math.min(slider.value / 1000, 0.99999);
  });
  $('speed').addEventListener('change', function () { speed = +this.value; });
  document.querySelectorAll('button.cam').forEach(function (b) {
    b.addEventListener('click', function () { activeView = b.dataset.view; setView(activeView); });
  });
  $('follow').addEventListener('change', function () { follow = this.checked; });
  $('show-muscles').addEventListener('change', function () { muscleMesh.visible = this.checked; });
  window.addEventListener('keydown', function (e) {
    if (e.target.tagName === 'INPUT' || e.target.tagName === 'SELECT') return;
    var n = decoded(current).n;
    if (e.code === 'Space') { setPlaying(!playing); e.preventDefault(); }
    if (e.code === 'ArrowRight' || e.code === 'ArrowLeft') {
      setPlaying(false);
      var step = e.code === 'ArrowRight' ? 1 : -1;
      phase = ((Math.round(phase * (n - 1)) + step + (n - 1)) % (n - 1)) / (n - 1);
    }
  });

  function resize() {
    var w = container.clientWidth || 1, h = container.clientHeight || 1;
    renderer.setSize(w, h, false);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
  }
  // resizing clears the canvas: draw again at once
  new ResizeObserver(function () {
    resize();
    if (current) frame();
  }).observe(container);

  function showClock() {
    var f = decoded(current);
    slider.value = Math.round(phase * 1000);
    $('clock').textContent = (phase * f.duration).toFixed(3) + ' s · ' + Math.round(phase * 100) + ' %';
  }
  function frame() {
    pose();
    followRoot();
    controls.update();
    renderer.render(scene, camera);
    drawPlots();
    showClock();
  }
  var last = null;
  function tick(now) {
    if (last !== null && playing) {
      var dt = Math.min((now - last) / 1000, 0.1);
      phase = (phase + dt * speed / decoded(current).duration) % 1;
    }
    last = now;
    frame();
    requestAnimationFrame(tick);
  }

  $('page-title').textContent = data.title.replace(/^stride — /, '');
  $('generator').textContent = 'Written by ' + data.generator + ' · model ' + model.name + ' · 3D: three.js (MIT)';
  buildCaseList();
  buildFigures();
  setPlaying(playing);
  resize();
  var firstCase = Math.min(Math.max(parseInt(params.get('case'), 10) || 0, 0), cases.length - 1);
  if (cases.length > 1) $('cases').value = String(firstCase);
  setCase(firstCase);
  setView(activeView);
  frame();
  if (document.documentElement.getAttribute('data-status') !== 'error') {
    document.documentElement.setAttribute('data-status', 'rendered');
  }
  requestAnimationFrame(tick);
})();
