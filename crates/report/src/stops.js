// cardan report: the end stops of a run with [[limit]] (crates/report/src/stops.rs). Only in
// such a page, before viewer.js, which calls window.cardanStops once its scene is built and the
// returned draw(t) at every frame drawn. It adds a red ring about each stop's joint axis at the
// joint, shown while the stop is active (held closed, pressed or struck), the list of the stops
// with their state and force (#stops; each entry's data-active is 1 while its ring is shown,
// also without WebGL), and a tick on the timeline at each impact (grey: a release; a click
// goes to it).
window.cardanStops = function (T, meta, built, findFrame) {
  'use strict';
  var data = meta.stops;
  if (!data || !data.list.length) return null;
  var times = built.times, n = times.length;
  var t0 = times[0], t1 = times[n - 1];

  // The rings: on the body the joint is drawn on, about the joint's axis, drawn over the parts.
  var r = (meta.extent || meta.size) / 30;
  var zAxis = new T.Vector3(0, 0, 1);
  var rings = data.list.map(function (s) {
    var mat = new T.MeshBasicMaterial({ color: 0xe00000, depthTest: false });
    var ring = new T.Mesh(new T.TorusGeometry(1.8 * r, 0.3 * r, 12, 48), mat);
    ring.renderOrder = 10;
    ring.position.fromArray(s.point);
    var d = new T.Vector3().fromArray(s.direction);
    if (d.lengthSq() > 0) ring.quaternion.setFromUnitVectors(zAxis, d.normalize());
    ring.visible = false;
    if (built.roots[s.body]) built.roots[s.body].add(ring);
    return ring;
  });

  // The list of the stops, below the controls.
  var list = document.createElement('div');
  list.id = 'stops';
  var entries = data.list.map(function (s) {
    var e = document.createElement('span');
    e.className = 'stop';
    e.setAttribute('data-stop', s.name);
    e.setAttribute('data-active', '0');
    e.title = 'end stop ' + s.name + ' of joint ' + s.joint;
    list.appendChild(e);
    return e;
  });
  var controls = document.getElementById('controls');
  controls.parentNode.insertBefore(list, controls.nextSibling);

  // The ticks: under the slider, at the thumb's centre for each event's time.
  var scrub = document.getElementById('scrub');
  var line = document.createElement('span');
  line.id = 'timeline';
  scrub.parentNode.insertBefore(line, scrub);
  line.appendChild(scrub);
  var ticks = document.createElement('span');
  ticks.id = 'stop-ticks';
  line.appendChild(ticks);
  (data.events || []).forEach(function (ev) {
    var time = ev[0], s = data.list[ev[1]], kind = ev[2];
    if (!s || !(t1 > t0)) return;
    var f = Math.max(0, Math.min(1, (time - t0) / (t1 - t0)));
    var tick = document.createElement('span');
    tick.className = 'tick ' + (kind === 'release' ? 'release' : 'impact');
    tick.style.left = 'calc(8px + (100% - 16px) * ' + f.toFixed(6) + ')';
    tick.title = 't = ' + time.toFixed(4) + ' s: ' + s.name + ' ' + kind.replace('_', ', ');
    tick.addEventListener('click', function () {
      scrub.value = time;
      scrub.dispatchEvent(new Event('input'));
    });
    ticks.appendChild(tick);
  });

  // Frame k stands for (t_{k-1}, t_k]: between two frames, the later one's state (a time a
  // hair past a frame, its single-precision copy, is that frame).
  function frameAt(t) {
    var f = findFrame(times, t);
    return f[1] > 1e-3 ? Math.min(f[0] + 1, n - 1) : f[0];
  }
  function describe(s, k) {
    var force = s.force[k];
    if (!s.active[k]) return s.name + ': open';
    if (force === 0) return s.name + ': impact';
    return s.name + ': closed, ' + force.toPrecision(4) + ' ' + s.unit;
  }
  var shown = [];
  function draw(t) {
    var k = frameAt(t);
    data.list.forEach(function (s, i) {
      var on = s.active[k] === 1;
      rings[i].visible = on;
      entries[i].setAttribute('data-active', on ? '1' : '0');
      entries[i].textContent = describe(s, k);
      if (on) shown.push(s.name);
    });
    document.body.setAttribute('data-stops-active', shown.join(' '));
    shown.length = 0;
  }
  return { draw: draw };
};
