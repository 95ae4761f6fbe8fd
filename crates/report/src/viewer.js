// cardan report viewer: reads the embedded .glb (nodes, meshes, materials, animation) and plays
// it with three.js. No network, no modules: runs from file://.
// Lines tagged [stops] call stops.js; a page without end stops has neither (html.rs). // [stops]
(function () {
  'use strict';
  var T = window.THREE;

  // --- the .glb -----------------------------------------------------------------------------
  function fromBase64(s) {
    var bin = atob(s.trim());
    var bytes = new Uint8Array(bin.length);
    for (var i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
    return bytes.buffer;
  }

  function parseGlb(buf) {
    var dv = new DataView(buf);
    if (dv.getUint32(0, true) !== 0x46546c67) throw new Error('the embedded animation is not a .glb');
    var json = null, bin = -1, off = 12;
    while (off + 8 <= dv.byteLength) {
      var len = dv.getUint32(off, true), type = dv.getUint32(off + 4, true);
      if (type === 0x4e4f534a) json = JSON.parse(new TextDecoder().decode(new Uint8Array(buf, off + 8, len)));
      else if (type === 0x004e4942) bin = off + 8;
      off += 8 + len;
    }
    if (!json) throw new Error('the .glb has no JSON chunk');
    return { json: json, buf: buf, bin: bin };
  }

  var WIDTH = { SCALAR: 1, VEC2: 2, VEC3: 3, VEC4: 4 };
  function accessor(g, i) {
    var a = g.json.accessors[i], v = g.json.bufferViews[a.bufferView];
    var off = g.bin + (v.byteOffset || 0) + (a.byteOffset || 0), n = a.count * WIDTH[a.type];
    if (a.componentType === 5126) return new Float32Array(g.buf, off, n);
    if (a.componentType === 5125) return new Uint32Array(g.buf, off, n);
    if (a.componentType === 5123) return new Uint16Array(g.buf, off, n);
    throw new Error('unsupported accessor component type ' + a.componentType);
  }

  function buildScene(g) {
    var j = g.json;
    var materials = (j.materials || []).map(function (m) {
      var pbr = m.pbrMetallicRoughness || {};
      var c = pbr.baseColorFactor || [1, 1, 1, 1];
      return new T.MeshStandardMaterial({
        color: new T.Color().setRGB(c[0], c[1], c[2]),
        metalness: pbr.metallicFactor === undefined ? 1 : pbr.metallicFactor,
        roughness: pbr.roughnessFactor === undefined ? 1 : pbr.roughnessFactor
      });
    });
    var meshes = (j.meshes || []).map(function (m) {
      var group = new T.Group();
      m.primitives.forEach(function (p) {
        var geo = new T.BufferGeometry();
        geo.setAttribute('position', new T.BufferAttribute(accessor(g, p.attributes.POSITION), 3));
        if (p.attributes.NORMAL !== undefined) geo.setAttribute('normal', new T.BufferAttribute(accessor(g, p.attributes.NORMAL), 3));
        else geo.computeVertexNormals();
        if (p.indices !== undefined) geo.setIndex(new T.BufferAttribute(accessor(g, p.indices), 1));
        var mat = p.material === undefined ? new T.MeshStandardMaterial() : materials[p.material];
        group.add(new T.Mesh(geo, mat));
      });
      return group;
    });
    var nodes = j.nodes.map(function (n) {
      var o = new T.Group();
      o.name = n.name || '';
      if (n.translation) o.position.fromArray(n.translation);
      if (n.rotation) o.quaternion.fromArray(n.rotation);
      if (n.scale) o.scale.fromArray(n.scale);
      if (n.mesh !== undefined) o.add(meshes[n.mesh].clone());
      return o;
    });
    j.nodes.forEach(function (n, i) {
      (n.children || []).forEach(function (c) { nodes[i].add(nodes[c]); });
    });
    var roots = j.scenes[j.scene || 0].nodes.map(function (i) { return nodes[i]; });
    var tracks = [], times = null;
    (j.animations || []).slice(0, 1).forEach(function (an) {
      an.channels.forEach(function (ch) {
        var s = an.samplers[ch.sampler];
        var input = accessor(g, s.input);
        times = times || input;
        tracks.push({ node: nodes[ch.target.node], path: ch.target.path, times: input, values: accessor(g, s.output) });
      });
    });
    return { roots: roots, tracks: tracks, times: times || new Float32Array([0]) };
  }

  // --- interpolation ----------------------------------------------------------------------
  function findFrame(times, t) {
    var lo = 0, hi = times.length - 1;
    if (t <= times[0]) return [0, 0];
    if (t >= times[hi]) return [hi, 0];
    while (hi - lo > 1) { var mid = (lo + hi) >> 1; if (times[mid] <= t) lo = mid; else hi = mid; }
    return [lo, (t - times[lo]) / (times[lo + 1] - times[lo])];
  }
  var tmp = new Float32Array(4);
  function applyTracks(tracks, t) {
    tracks.forEach(function (tr) {
      var f = findFrame(tr.times, t), k = f[0], a = f[1], v = tr.values;
      var k1 = Math.min(k + 1, tr.times.length - 1);
      if (tr.path === 'translation') {
        tr.node.position.set(
          v[3 * k] + a * (v[3 * k1] - v[3 * k]),
          v[3 * k + 1] + a * (v[3 * k1 + 1] - v[3 * k + 1]),
          v[3 * k + 2] + a * (v[3 * k1 + 2] - v[3 * k + 2]));
      } else if (tr.path === 'rotation') {
        T.Quaternion.slerpFlat(tmp, 0, v, 4 * k, v, 4 * k1, a);
        tr.node.quaternion.fromArray(tmp);
      }
    });
  }

  // --- WebGL ------------------------------------------------------------------------------
  // Whether the browser gives a WebGL context, asked on a canvas of its own (the view's
  // canvas must stay free for three.js to choose its context attributes).
  function webglAvailable() {
    try {
      var probe = document.createElement('canvas');
      return !!(window.WebGLRenderingContext && (probe.getContext('webgl2') || probe.getContext('webgl')));
    } catch (e) {
      return false;
    }
  }

  // The renderer, or null without WebGL: then one sentence replaces the 3D view (not three.js's
  // error dump), and the timeline, the plots and the summary work as before.
  function makeRenderer(canvas) {
    var r = null;
    if (webglAvailable()) {
      try {
        r = new T.WebGLRenderer({ canvas: canvas, antialias: true, preserveDrawingBuffer: true });
        r.setPixelRatio(window.devicePixelRatio || 1);
      } catch (e) {
        r = null;
      }
    }
    if (!r) {
      var note = document.createElement('p');
      note.id = 'no-webgl';
      note.className = 'notice';
      note.textContent = '3D view needs WebGL; the plots below work without it.';
      canvas.style.display = 'none';
      canvas.parentNode.classList.add('no-webgl');
      canvas.parentNode.appendChild(note);
      document.body.setAttribute('data-webgl', '0');
    }
    return r;
  }

  // --- page -------------------------------------------------------------------------------
  var canvas = document.getElementById('canvas');
  var renderer = makeRenderer(canvas);
  var scene = new T.Scene();
  scene.background = new T.Color(0xf4f5f7);
  scene.add(new T.HemisphereLight(0xffffff, 0x888899, 2.0));
  var sun = new T.DirectionalLight(0xffffff, 1.5);
  scene.add(sun);
  var camera = new T.PerspectiveCamera(40, 1, 1e-3, 1e3);
  var trailBox = document.getElementById('trails');
  var palette = [0x0072b2, 0xd55e00, 0x009e73, 0xcc79a7, 0xe69f00, 0x56b4e9, 0x8c564b];

  // The model shown: its data, its scene objects and its time span. `show` builds it from the
  // page's data and again, in place, for each update of the live preview (`replace`).
  var meta = null, built = null, size = 1, up = new T.Vector3(0, 0, 1);
  var frameHelpers = [], axisHelpers = [], trails = [];
  var t0 = 0, t1 = 0;

  function dispose(root) {
    root.traverse(function (o) {
      if (o.geometry) o.geometry.dispose();
      if (o.material) o.material.dispose();
    });
  }

  // Returns the old model's objects, removed from the scene: disposed after the new model is
  // drawn, so that three.js keeps the compiled shaders they share (disposing the last material
  // of a shader deletes it, and compiling it again costs a software renderer ~0.3 s).
  function show(newMeta, glb) {
    var checked = {}, old = [];
    if (built) {
      built.roots.forEach(function (r) { scene.remove(r); old.push(r); });
      trails.forEach(function (tr) { checked[tr.name] = tr.box.checked; scene.remove(tr.line); old.push(tr.line); });
    }
    meta = newMeta;
    built = buildScene(glb);
    built.roots.forEach(function (r) { scene.add(r); });
    size = meta.size;
    up = new T.Vector3().fromArray(meta.up).normalize();
    camera.up.copy(up);
    camera.near = size * 1e-3; camera.far = size * 1e3; camera.updateProjectionMatrix();

    // Body frames and joint axes (hidden until toggled).
    var showFrames = document.getElementById('frames').checked;
    var showAxes = document.getElementById('axes').checked;
    frameHelpers = []; axisHelpers = [];
    var armLength = 0.15 * size;
    built.roots.forEach(function (r) {
      var h = new T.AxesHelper(armLength); h.visible = showFrames; r.add(h); frameHelpers.push(h);
    });
    (meta.axes || []).forEach(function (a) {
      var root = built.roots[a.body]; if (!root) return;
      var d = new T.Vector3().fromArray(a.direction).normalize();
      var p = new T.Vector3().fromArray(a.point);
      var half = 0.2 * size;
      var geo = new T.BufferGeometry().setFromPoints([p.clone().addScaledVector(d, -half), p.clone().addScaledVector(d, half)]);
      var line = new T.Line(geo, new T.LineBasicMaterial({ color: 0xd4a017 }));
      line.visible = showAxes; root.add(line); axisHelpers.push(line);
    });

    // Trails: each named point's path over the keyframes, drawn up to the current time.
    trails = [];
    trailBox.textContent = '';
    (meta.bodies || []).forEach(function (b, bi) {
      var root = built.roots[bi];
      var tr = built.tracks.filter(function (t) { return t.node === root; });
      if (!tr.length) return;
      b.points.forEach(function (pt) {
        var times = built.times, n = times.length;
        var stride = Math.max(1, Math.ceil(n / 20000));
        var pts = [], sampleTimes = [];
        var saved = [root.position.clone(), root.quaternion.clone()];
        for (var k = 0; k < n; k += stride) {
          applyTracks(tr, times[k]);
          root.updateMatrix();
          pts.push(new T.Vector3().fromArray(pt.local).applyMatrix4(root.matrix));
          sampleTimes.push(times[k]);
        }
        root.position.copy(saved[0]); root.quaternion.copy(saved[1]);
        var name = b.name + '.' + pt.name;
        var geo = new T.BufferGeometry().setFromPoints(pts);
        var line = new T.Line(geo, new T.LineBasicMaterial({ color: palette[trails.length % palette.length] }));
        line.visible = !!checked[name]; line.frustumCulled = false; scene.add(line);
        var label = document.createElement('label');
        var box = document.createElement('input'); box.type = 'checkbox'; box.checked = line.visible;
        box.addEventListener('change', function () { line.visible = box.checked; draw(); });
        label.appendChild(box); label.appendChild(document.createTextNode(' ' + name));
        trailBox.appendChild(label);
        trails.push({ line: line, times: sampleTimes, name: name, box: box });
      });
    });
    if (!trails.length) trailBox.textContent = 'no named points on moving bodies';
    t0 = built.times[0]; t1 = built.times[built.times.length - 1];
    return old;
  }

  show(JSON.parse(document.getElementById('meta').textContent),
    parseGlb(fromBase64(document.getElementById('glb').textContent)));

  // Orbit: spherical coordinates about the target, around the up direction.
  var target = new T.Vector3().fromArray(meta.centre), radius = 1.25 * size, azimuth = 0.6, elevation = 0.45;
  var basisX = new T.Vector3(), basisY = new T.Vector3();
  function orbitBasis() {
    var ref = Math.abs(up.z) < 0.9 ? new T.Vector3(0, 0, 1) : new T.Vector3(1, 0, 0);
    basisY.crossVectors(up, ref).normalize();
    basisX.crossVectors(basisY, up).normalize();
  }
  orbitBasis();
  function placeCamera() {
    var ce = Math.cos(elevation);
    var dir = basisX.clone().multiplyScalar(ce * Math.cos(azimuth))
      .addScaledVector(basisY, ce * Math.sin(azimuth)).addScaledVector(up, Math.sin(elevation));
    camera.position.copy(target).addScaledVector(dir, radius);
    camera.lookAt(target);
    sun.position.copy(camera.position).addScaledVector(up, size);
  }

  // Picking and dragging a body (Ctrl- or Alt-drag) for a host that sets
  // `cardanReport.dragHandler` (the live preview, `cardan watch`): start({body, index, point,
  // t}), move(target), end(), points in world coordinates; the host answers with poses
  // (`cardanReport.setPoses`). The target moves in the plane through the picked point facing
  // the camera.
  var raycaster = new T.Raycaster();
  function rayAt(x, y) {
    var rect = canvas.getBoundingClientRect();
    var ndc = new T.Vector2(2 * (x - rect.left) / rect.width - 1, 1 - 2 * (y - rect.top) / rect.height);
    camera.updateMatrixWorld();
    raycaster.setFromCamera(ndc, camera);
    return raycaster.ray;
  }
  function pick(x, y) {
    rayAt(x, y);
    var hits = raycaster.intersectObjects(built.roots, true).filter(function (h) { return h.object.isMesh && h.object.visible; });
    if (!hits.length) return null;
    var o = hits[0].object;
    while (o && built.roots.indexOf(o) < 0) o = o.parent;
    var index = built.roots.indexOf(o);
    return { body: meta.bodies[index].name, index: index, point: hits[0].point.toArray(), t: t };
  }
  var api = window.cardanReport = { dragHandler: null, replaced: 0 };
  var posed = false, dragPlane = null;

  var drag = null;
  canvas.addEventListener('contextmenu', function (e) { e.preventDefault(); });
  canvas.addEventListener('pointerdown', function (e) {
    if ((e.ctrlKey || e.altKey) && api.dragHandler && !modes) {
      var hit = pick(e.clientX, e.clientY);
      if (!hit) return;
      var normal = new T.Vector3();
      camera.getWorldDirection(normal);
      dragPlane = new T.Plane().setFromNormalAndCoplanarPoint(normal, new T.Vector3().fromArray(hit.point));
      setPlaying(false);
      canvas.setPointerCapture(e.pointerId);
      api.dragHandler.start(hit);
      return;
    }
    drag = { x: e.clientX, y: e.clientY, pan: e.button === 2 || e.shiftKey };
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener('pointerup', function () {
    drag = null;
    if (dragPlane) { dragPlane = null; if (api.dragHandler) api.dragHandler.end(); }
  });
  canvas.addEventListener('pointermove', function (e) {
    if (dragPlane) {
      var p = rayAt(e.clientX, e.clientY).intersectPlane(dragPlane, new T.Vector3());
      if (p && api.dragHandler) api.dragHandler.move(p.toArray());
      return;
    }
    if (!drag) return;
    var dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    drag.x = e.clientX; drag.y = e.clientY;
    if (drag.pan) {
      var s = radius / canvas.clientHeight;
      var right = new T.Vector3().setFromMatrixColumn(camera.matrix, 0);
      var camUp = new T.Vector3().setFromMatrixColumn(camera.matrix, 1);
      target.addScaledVector(right, -dx * s).addScaledVector(camUp, dy * s);
    } else {
      azimuth -= dx * 0.01;
      elevation = Math.max(-1.55, Math.min(1.55, elevation + dy * 0.01));
    }
    placeCamera(); draw();
  });
  canvas.addEventListener('wheel', function (e) {
    e.preventDefault();
    radius = Math.max(size * 0.01, Math.min(size * 100, radius * Math.exp(e.deltaY * 0.001)));
    placeCamera(); draw();
  }, { passive: false });

  // Vibration modes (a modal run): each body at r0 + s dr, p ∝ p0 + s dp with
  // s = g a sin(2πτ), τ the phase in periods (crates/report/src/modes.rs).
  var modes = meta.modes || null;
  var mode = null, gain = 1;
  var modeSelect = document.getElementById('mode');
  var gainInput = document.getElementById('amplitude');
  var gainLabel = document.getElementById('amplitude-value');
  var posesOut = document.getElementById('mode-poses');
  function selectMode(i) {
    mode = modes.list[Math.max(0, Math.min(modes.list.length - 1, i))];
    modeSelect.value = String(modes.list.indexOf(mode));
    document.body.setAttribute('data-mode', String(mode.number));
  }
  function showGain() {
    var pct = 100 * gain * modes.fraction;
    gainLabel.textContent = '×' + gain.toFixed(2) + ' (largest motion ' + pct.toFixed(0) + ' % of the model size)';
  }
  var modeQuat = new T.Quaternion();
  function applyMode(tau) {
    var s = gain * mode.amplitude * Math.sin(2 * Math.PI * tau);
    var poses = posesOut && recordPoses ? [] : null;
    modes.rest.forEach(function (q0, bi) {
      var phi = mode.shape[bi], root = built.roots[bi];
      if (!q0 || !phi || !root) { if (poses) poses.push(null); return; }
      var r = q0[0], p = q0[1];
      var e = [p[0] + s * phi[3], p[1] + s * phi[4], p[2] + s * phi[5], p[3] + s * phi[6]];
      var n = Math.sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3]);
      var x = r[0] + s * phi[0], y = r[1] + s * phi[1], z = r[2] + s * phi[2];
      root.position.set(x, y, z);
      root.quaternion.copy(modeQuat.set(e[1] / n, e[2] / n, e[3] / n, e[0] / n));
      if (poses) poses.push([x, y, z, e[0] / n, e[1] / n, e[2] / n, e[3] / n]);
    });
    if (poses) posesOut.textContent = JSON.stringify({ mode: mode.number, tau: tau, s: s, bodies: poses });
  }
  var recordPoses = false;
  if (modes && modes.list.length) {
    var q = new URLSearchParams(window.location.search);
    var wanted = parseInt(q.get('mode'), 10);
    selectMode(isFinite(wanted) ? wanted - 1 : 0);
    var given = parseFloat(q.get('amplitude'));
    if (isFinite(given) && given >= 0) { gain = given; gainInput.value = String(given); }
    showGain();
    document.getElementById('trails-box').hidden = true;
    modeSelect.addEventListener('change', function () { selectMode(parseInt(modeSelect.value, 10)); draw(); });
    gainInput.addEventListener('input', function () { gain = parseFloat(gainInput.value); showGain(); draw(); });
  } else {
    modes = null;
  }
  var stops = !modes && window.cardanStops ? window.cardanStops(T, meta, built, findFrame) : null; // [stops]

  // Playback (a modal run: the phase τ over one period, a period per second at speed 1).
  if (modes) { t0 = 0; t1 = 1; document.getElementById('scrub').setAttribute('aria-label', 'phase'); }
  var t = t0, playing = t1 > t0, speed = 1, last = null;
  var playBtn = document.getElementById('play'), scrub = document.getElementById('scrub');
  var timeLabel = document.getElementById('time');
  scrub.min = t0; scrub.max = t1; scrub.step = 'any';
  var query = new URLSearchParams(window.location.search).get(modes ? 'tau' : 't');
  if (query !== null && isFinite(parseFloat(query))) {
    t = Math.max(t0, Math.min(t1, parseFloat(query))); playing = false;
    recordPoses = !!modes;
  }
  function setPlaying(p) { playing = p && t1 > t0; playBtn.textContent = playing ? 'pause' : 'play'; last = null; if (playing) posed = false; }
  playBtn.addEventListener('click', function () { setPlaying(!playing); if (playing) requestAnimationFrame(tick); });
  scrub.addEventListener('input', function () { t = parseFloat(scrub.value); setPlaying(false); posed = false; draw(); });
  document.getElementById('speed').addEventListener('change', function (e) { speed = parseFloat(e.target.value); });
  document.getElementById('frames').addEventListener('change', function (e) {
    frameHelpers.forEach(function (h) { h.visible = e.target.checked; }); draw();
  });
  document.getElementById('axes').addEventListener('change', function (e) {
    axisHelpers.forEach(function (h) { h.visible = e.target.checked; }); draw();
  });

  function resize() {
    var w = canvas.clientWidth || 800, h = canvas.clientHeight || 480;
    if (renderer) renderer.setSize(w, h, false);
    camera.aspect = w / h; camera.updateProjectionMatrix();
  }
  function draw() {
    if (modes) {
      applyMode(t);
      timeLabel.textContent = 'mode ' + mode.number + ', τ = ' + t.toFixed(3) + ' T';
    } else {
      if (!posed) applyTracks(built.tracks, t);
      trails.forEach(function (tr) { tr.line.geometry.setDrawRange(0, findFrame(tr.times, t)[0] + 1); });
      if (stops) stops.draw(t); // [stops]
      timeLabel.textContent = 't = ' + t.toFixed(4) + ' s' + (posed ? ' (dragged)' : '');
    }
    scrub.value = t;
    if (renderer) renderer.render(scene, camera);
  }
  function tick(now) {
    if (!playing) return;
    if (last !== null) {
      t += (now - last) / 1000 * speed;
      if (t > t1) t = t0 + (t - t0) % (t1 - t0);
    }
    last = now;
    draw();
    requestAnimationFrame(tick);
  }
  window.addEventListener('resize', function () { resize(); draw(); });

  // The live preview's hooks (`cardan watch`, crates/cli/src/watch/page.html).
  // replace(update): the model of a new solve shown in place (update: `glb` in base64, `meta`,
  // the `plots` and `summary` sections' HTML), the camera, time and toggles kept; false when
  // either page is not `replaceable` (a modal run or a run with limits: their controls are
  // part of the page, the host loads the new page instead).
  api.replace = function (update) {
    if (!meta.replaceable || !update.meta.replaceable) return false;
    var oldUp = up.clone();
    var old = show(update.meta, parseGlb(fromBase64(update.glb)));
    if (!up.equals(oldUp)) orbitBasis();
    scrub.min = t0; scrub.max = t1;
    t = Math.max(t0, Math.min(t1, t));
    if (!(t1 > t0)) setPlaying(false);
    document.getElementById('plots').innerHTML = update.plots;
    document.getElementById('summary').innerHTML = update.summary;
    posed = false;
    placeCamera(); draw();
    old.forEach(dispose);
    api.replaced += 1;
    document.body.setAttribute('data-replaced', String(api.replaced));
    return true;
  };
  // setPoses(poses): each body at [x, y, z, e0, e1, e2, e3] (null: where it is) until the
  // time moves or the playback starts.
  api.setPoses = function (poses) {
    poses.forEach(function (q, bi) {
      var root = built.roots[bi];
      if (!q || !root) return;
      root.position.set(q[0], q[1], q[2]);
      root.quaternion.set(q[4], q[5], q[6], q[3]).normalize();
    });
    posed = true; setPlaying(false); draw();
  };
  // project(index, local): where a point of a body is on the screen (client pixels).
  api.project = function (index, local) {
    var root = built.roots[index];
    root.updateMatrixWorld();
    var p = new T.Vector3().fromArray(local).applyMatrix4(root.matrixWorld).project(camera);
    var rect = canvas.getBoundingClientRect();
    return { x: rect.left + (p.x + 1) / 2 * rect.width, y: rect.top + (1 - p.y) / 2 * rect.height };
  };
  // pose(index): a body's pose as drawn, [x, y, z, e0, e1, e2, e3]; bodies(): their names.
  api.pose = function (index) {
    var r = built.roots[index], q = r.quaternion;
    return [r.position.x, r.position.y, r.position.z, q.w, q.x, q.y, q.z];
  };
  api.bodies = function () { return meta.bodies.map(function (b) { return b.name; }); };
  api.time = function () { return t; };

  resize(); placeCamera(); setPlaying(playing); draw();
  document.body.setAttribute('data-ready', '1');
  if (playing) requestAnimationFrame(tick);
})();
