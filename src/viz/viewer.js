// idto viewer: animates the scene data of the page (the JSON block #idto-scene, written by
// idto::WriteHtmlAnimation) with three.js r111.
//
// Scene data layout (positions in m, quaternions as x, y, z, w, forces in N):
//   title, models: [{name, color}], bodies: [{name, model, pose: [p, q]}] (index = body index;
//   the pose is the first frame's, constant for the bodies not in `animated`),
//   animated: [body index], geometries: [{name, body, type, radius, length, size, pose, color}],
//   bones: [{body, to: [x, y, z] in the body}] (rods from the body origin to its children's
//   joints and its shapes' origins),
//   center, radius (extent of the scene), force_scale (m/N), max_force, has_contact_model,
//   speed, show: {forces, ghost, frames},
//   times: [t_k], poses: [[7 per animated body] per frame], ghost: [[7 per animated body, or
//   empty] per frame], contacts: [[10 per contact: p (3), normal force (3), friction (3), phi]
//   per frame] (the force on the moving body of the pair).
//
// URL fragment: #t=1.5 opens paused at t = 1.5 s; #idto-test=<JSON> runs the test driver at
// the end of this file (used by idto's browser tests) and writes its report into
// #idto-test-output.
'use strict';
// A block, not a function: its declarations stay out of the global scope.
{
  let S = JSON.parse(document.getElementById('idto-scene').textContent);
  let N = S.times.length;
  let T0 = S.times[0];
  let T1 = S.times[N - 1];
  let R = S.radius;
  let CENTER = new THREE.Vector3().fromArray(S.center);
  let Y_AXIS = new THREE.Vector3(0, 1, 0);
  let COLORS = {
    normal: 0xd62728, normal_distance: 0xff9896, friction: 0x2ca02c, friction_distance: 0x98df8a
  };

  // ---------------------------------------------------------------- renderer, camera, lights
  let view = document.getElementById('view');
  let renderer = new THREE.WebGLRenderer({antialias: false, preserveDrawingBuffer: true});
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  view.appendChild(renderer.domElement);
  let scene = new THREE.Scene();
  scene.background = new THREE.Color(0xf4f5f7);
  let camera = new THREE.PerspectiveCamera(40, 1, R * 0.005, R * 200);
  camera.up.set(0, 0, 1);  // Z up
  let view_dir = new THREE.Vector3(0.9, -1.6, 0.75).normalize();
  camera.position.copy(CENTER).addScaledVector(view_dir, 3.1 * R);
  let controls = new THREE.OrbitControls(camera, renderer.domElement);
  controls.target.copy(CENTER);
  controls.screenSpacePanning = true;
  controls.update();
  let hemi = new THREE.HemisphereLight(0xffffff, 0x707070, 0.75);
  hemi.position.set(0, 0, 1);
  scene.add(hemi);
  let sun = new THREE.DirectionalLight(0xffffff, 0.55);
  sun.position.set(CENTER.x + R, CENTER.y - 2 * R, CENTER.z + 3 * R);
  scene.add(sun);
  let world_axes = new THREE.AxesHelper(0.5 * R);
  scene.add(world_axes);

  // ---------------------------------------------------------------- shapes
  let geometry_cache = {};
  function cached(key, make) {
    if (!geometry_cache[key]) geometry_cache[key] = make();
    return geometry_cache[key];
  }
  function sphereGeometry(r) {
    return cached('s' + r, function () { return new THREE.SphereBufferGeometry(r, 16, 12); });
  }
  function cylinderGeometry(r, l) {
    return cached('c' + r + ',' + l, function () {
      var g = new THREE.CylinderBufferGeometry(r, r, l, 24);
      g.rotateX(Math.PI / 2);  // three.js cylinders run along Y; idto's along Z
      return g;
    });
  }
  function boxGeometry(s) {
    return cached('b' + s.join(','), function () {
      return new THREE.BoxBufferGeometry(s[0], s[1], s[2]);
    });
  }
  function setPose(object, pose) {
    object.position.set(pose[0], pose[1], pose[2]);
    object.quaternion.set(pose[3], pose[4], pose[5], pose[6]);
  }
  // The meshes of a shape in its frame (capsule = cylinder + two spheres); null for half-spaces.
  function makeShape(g, material) {
    var shape = new THREE.Group();
    if (g.type === 'sphere') {
      shape.add(new THREE.Mesh(sphereGeometry(g.radius), material));
    } else if (g.type === 'box') {
      shape.add(new THREE.Mesh(boxGeometry(g.size), material));
    } else if (g.type === 'cylinder') {
      shape.add(new THREE.Mesh(cylinderGeometry(g.radius, g.length), material));
    } else if (g.type === 'capsule') {
      shape.add(new THREE.Mesh(cylinderGeometry(g.radius, g.length), material));
      for (var side = -1; side <= 1; side += 2) {
        var cap = new THREE.Mesh(sphereGeometry(g.radius), material);
        cap.position.z = side * 0.5 * g.length;
        shape.add(cap);
      }
    } else {
      return null;
    }
    setPose(shape, g.pose);
    return shape;
  }
  function niceStep(x) {
    var p = Math.pow(10, Math.floor(Math.log10(x)));
    var m = x / p;
    return (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10) * p;
  }
  // A half-space: a grid and a translucent plane in its boundary, around the scene's centre.
  function makeGround(g, body_pose) {
    var ground = new THREE.Group();
    setPose(ground, g.pose);
    var step = niceStep(R / 4);
    var size = 2 * step * Math.ceil(2.5 * R / step);
    var grid = new THREE.GridHelper(size, Math.round(size / step), 0x8a8f98, 0xc4c8ce);
    grid.rotation.x = Math.PI / 2;  // GridHelper lies in XZ; the half-space boundary is XY
    var plane = new THREE.Mesh(new THREE.PlaneBufferGeometry(size, size),
        new THREE.MeshLambertMaterial({color: 0xdde1e6, transparent: true, opacity: 0.6,
                                       side: THREE.DoubleSide, depthWrite: false}));
    plane.position.z = -1e-4 * R;
    // Centre the grid under the scene, on grid lines.
    var frame = new THREE.Object3D();
    setPose(frame, body_pose);
    var inner = new THREE.Object3D();
    setPose(inner, g.pose);
    frame.add(inner);
    frame.updateMatrixWorld(true);
    var c = inner.worldToLocal(CENTER.clone());
    var offset = new THREE.Vector3(step * Math.round(c.x / step), step * Math.round(c.y / step), 0);
    grid.position.copy(offset);
    plane.position.x = offset.x;
    plane.position.y = offset.y;
    ground.add(grid);
    ground.add(plane);
    return ground;
  }

  // ---------------------------------------------------------------- bodies, ghost, frames
  let body_groups = [];
  let ghost_groups = {};
  let frame_axes = [];
  let animated_slot = {};  // body index -> slot in the per-frame pose arrays
  S.animated.forEach(function (b, slot) { animated_slot[b] = slot; });
  let has_ghost = S.ghost.some(function (g) { return g.length > 0; });
  let materials = {};
  let ghost_materials = {};
  function material(color) {
    if (!materials[color]) {
      materials[color] = new THREE.MeshLambertMaterial({color: color});
    }
    return materials[color];
  }
  function ghostMaterial(color) {
    if (!ghost_materials[color]) {
      ghost_materials[color] = new THREE.MeshLambertMaterial(
          {color: color, transparent: true, opacity: 0.28, depthWrite: false});
    }
    return ghost_materials[color];
  }
  S.bodies.forEach(function (body, b) {
    var group = new THREE.Group();
    group.name = body.name;
    setPose(group, body.pose);
    scene.add(group);
    body_groups.push(group);
    if (b > 0) {
      var axes = new THREE.AxesHelper(0.12 * R);
      axes.visible = false;
      group.add(axes);
      frame_axes.push(axes);
    }
    if (has_ghost && animated_slot[b] !== undefined) {
      var ghost = new THREE.Group();
      ghost.name = body.name + ' (ghost)';
      scene.add(ghost);
      ghost_groups[b] = ghost;
    }
  });
  S.geometries.forEach(function (g) {
    if (g.type === 'half_space') {
      body_groups[g.body].add(makeGround(g, S.bodies[g.body].pose));
      return;
    }
    body_groups[g.body].add(makeShape(g, material(g.color)));
    if (ghost_groups[g.body]) ghost_groups[g.body].add(makeShape(g, ghostMaterial(g.color)));
  });

  // Bones (links drawn as thin rods from the body origin) and joint markers, model coloured.
  let bone_geometry = new THREE.CylinderBufferGeometry(1, 1, 1, 8);
  bone_geometry.translate(0, 0.5, 0);
  let bone_radius = 0.006 * R;
  let joint_geometry = new THREE.SphereBufferGeometry(1.8 * bone_radius, 12, 8);
  let has_joint_marker = {};
  function modelColor(b) {
    var m = S.bodies[b].model;
    return m >= 0 ? S.models[m].color : '#8c8c8c';
  }
  function addBone(group, to, mat, b) {
    var bone = new THREE.Mesh(bone_geometry, mat);
    var v = new THREE.Vector3().fromArray(to);
    bone.scale.set(bone_radius, v.length(), bone_radius);
    bone.quaternion.setFromUnitVectors(Y_AXIS, v.clone().normalize());
    group.add(bone);
    if (b !== undefined && !has_joint_marker[b]) {
      group.add(new THREE.Mesh(joint_geometry, mat));
      has_joint_marker[b] = true;
    }
  }
  S.bones.forEach(function (bone) {
    var color = modelColor(bone.body);
    addBone(body_groups[bone.body], bone.to, material(color), bone.body);
    if (ghost_groups[bone.body]) addBone(ghost_groups[bone.body], bone.to, ghostMaterial(color));
  });

  // ---------------------------------------------------------------- contact forces
  let unit_shaft = new THREE.CylinderBufferGeometry(1, 1, 1, 10);
  unit_shaft.translate(0, 0.5, 0);
  let unit_head = new THREE.ConeBufferGeometry(1, 1, 14);
  unit_head.translate(0, 0.5, 0);
  let point_geometry = new THREE.SphereBufferGeometry(0.018 * R, 12, 8);
  // Forces are drawn over everything (no depth test): a contact point is usually hidden
  // inside the bodies that touch.
  function arrowMaterial(color, at_distance) {
    return new THREE.MeshBasicMaterial({color: color, transparent: true, depthTest: false,
                                        opacity: at_distance ? 0.55 : 1.0});
  }
  let arrow_materials = {
    normal: arrowMaterial(COLORS.normal, false),
    normal_distance: arrowMaterial(COLORS.normal_distance, true),
    friction: arrowMaterial(COLORS.friction, false),
    friction_distance: arrowMaterial(COLORS.friction_distance, true)
  };
  let point_materials = {
    penetration: new THREE.MeshBasicMaterial({color: 0x7f0000, transparent: true,
                                              depthTest: false}),
    distance: new THREE.MeshBasicMaterial({color: 0xe07b00, wireframe: true, transparent: true,
                                           depthTest: false})
  };
  let forces_group = new THREE.Group();
  forces_group.renderOrder = 10;
  scene.add(forces_group);
  function Arrow() {
    this.group = new THREE.Group();
    this.shaft = new THREE.Mesh(unit_shaft, arrow_materials.normal);
    this.head = new THREE.Mesh(unit_head, arrow_materials.normal);
    this.group.add(this.shaft);
    this.group.add(this.head);
  }
  let scratch = new THREE.Vector3();
  Arrow.prototype.set = function (origin, f, mat) {
    var length = Math.sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]) * S.force_scale;
    this.group.visible = length > 1e-6 * R;
    if (!this.group.visible) return;
    var head = Math.min(0.35 * length, 0.07 * R);
    var shaft_radius = Math.min(0.008 * R, 0.3 * head);
    this.shaft.material = this.head.material = mat;
    this.shaft.scale.set(shaft_radius, length - head, shaft_radius);
    this.head.position.y = length - head;
    this.head.scale.set(0.4 * head, head, 0.4 * head);
    this.group.position.copy(origin);
    scratch.set(f[0], f[1], f[2]).normalize();
    this.group.quaternion.setFromUnitVectors(Y_AXIS, scratch);
  };
  let contact_pool = [];  // {normal: Arrow, friction: Arrow, point: Mesh}
  function contactSlot(i) {
    while (contact_pool.length <= i) {
      var c = {normal: new Arrow(), friction: new Arrow(),
               point: new THREE.Mesh(point_geometry, point_materials.penetration)};
      forces_group.add(c.normal.group);
      forces_group.add(c.friction.group);
      forces_group.add(c.point);
      contact_pool.push(c);
    }
    return contact_pool[i];
  }
  let shown_contacts = 0;
  let origin = new THREE.Vector3();
  function showContacts(k) {
    var data = S.contacts[k];
    var n = data.length / 10;
    for (var i = 0; i < n; ++i) {
      var c = contactSlot(i);
      var d = data.slice(10 * i, 10 * i + 10);
      var at_distance = d[9] > 0;
      origin.set(d[0], d[1], d[2]);
      c.normal.set(origin, d.slice(3, 6),
                   at_distance ? arrow_materials.normal_distance : arrow_materials.normal);
      c.friction.set(origin, d.slice(6, 9),
                     at_distance ? arrow_materials.friction_distance : arrow_materials.friction);
      c.point.position.copy(origin);
      c.point.material = at_distance ? point_materials.distance : point_materials.penetration;
      c.point.visible = true;
    }
    for (var j = n; j < shown_contacts; ++j) {
      contact_pool[j].normal.group.visible = false;
      contact_pool[j].friction.group.visible = false;
      contact_pool[j].point.visible = false;
    }
    shown_contacts = n;
  }

  // ---------------------------------------------------------------- time
  let current_t = T0;
  let current_frame = 0;
  let qa = new THREE.Quaternion();
  let qb = new THREE.Quaternion();
  function frameAt(t) {  // the last frame at or before t
    var lo = 0;
    var hi = N - 1;
    while (lo < hi) {
      var mid = (lo + hi + 1) >> 1;
      if (S.times[mid] <= t) lo = mid; else hi = mid - 1;
    }
    return lo;
  }
  function placeBodies(groups, poses_a, poses_b, alpha) {
    S.animated.forEach(function (b, slot) {
      var group = groups[b];
      var i = 7 * slot;
      var a = poses_a;
      var c = poses_b;
      group.position.set(a[i] + alpha * (c[i] - a[i]), a[i + 1] + alpha * (c[i + 1] - a[i + 1]),
                         a[i + 2] + alpha * (c[i + 2] - a[i + 2]));
      qa.set(a[i + 3], a[i + 4], a[i + 5], a[i + 6]);
      qb.set(c[i + 3], c[i + 4], c[i + 5], c[i + 6]);
      THREE.Quaternion.slerp(qa, qb, group.quaternion, alpha);
    });
  }
  let slider = document.getElementById('slider');
  let time_label = document.getElementById('time');
  let needs_render = true;
  // Shows the scene at time t (clamped to the trajectory): body poses interpolated between the
  // frames around t, contacts of the nearest frame.
  function setTime(t) {
    t = Math.min(Math.max(t, T0), T1);
    current_t = t;
    var k = frameAt(t);
    var k1 = Math.min(k + 1, N - 1);
    var gap = S.times[k1] - S.times[k];
    var alpha = gap > 0 ? (t - S.times[k]) / gap : 0;
    placeBodies(body_groups, S.poses[k], S.poses[k1], alpha);
    var ghost_here = has_ghost && S.ghost[k].length > 0;
    if (ghost_here) {
      placeBodies(ghost_groups, S.ghost[k], S.ghost[k1].length ? S.ghost[k1] : S.ghost[k],
                  alpha);
    }
    current_frame = alpha < 0.5 ? k : k1;
    showContacts(current_frame);
    var ghost_on = ghost_here && document.getElementById('show-ghost').checked;
    Object.keys(ghost_groups).forEach(function (b) { ghost_groups[b].visible = ghost_on; });
    slider.value = String(t);
    time_label.textContent = 't = ' + t.toFixed(3) + ' s / ' + T1.toFixed(3) + ' s';
    needs_render = true;
  }
  slider.min = String(T0);
  slider.max = String(T1);
  slider.step = 'any';
  slider.addEventListener('input', function () {
    setPlaying(false);
    setTime(parseFloat(slider.value));
  });

  // ---------------------------------------------------------------- controls
  let playing = false;
  let last_ms = null;
  let speed = S.speed;
  let play_button = document.getElementById('play');
  function setPlaying(on) {
    playing = on && T1 > T0;
    last_ms = null;
    play_button.innerHTML = playing ? '&#10074;&#10074;' : '&#9654;';
    if (playing && current_t >= T1) setTime(T0);
  }
  play_button.addEventListener('click', function () { setPlaying(!playing); });
  document.addEventListener('keydown', function (e) {
    if (e.target && e.target.tagName === 'SELECT') return;
    if (e.key === ' ') { setPlaying(!playing); e.preventDefault(); }
    if (e.key === 'ArrowRight') { setPlaying(false); setTime(S.times[Math.min(N - 1, current_frame + 1)]); }
    if (e.key === 'ArrowLeft') { setPlaying(false); setTime(S.times[Math.max(0, current_frame - 1)]); }
  });
  let speed_select = document.getElementById('speed');
  let best = speed_select.options[0];
  Array.prototype.forEach.call(speed_select.options, function (o) {
    if (Math.abs(Math.log(o.value / speed)) < Math.abs(Math.log(best.value / speed))) best = o;
  });
  speed_select.value = best.value;
  speed = parseFloat(best.value);
  speed_select.addEventListener('change', function () { speed = parseFloat(speed_select.value); });
  function checkbox(id, initial, apply) {
    var box = document.getElementById(id);
    box.checked = initial;
    box.addEventListener('change', function () { apply(box.checked); needs_render = true; });
    apply(initial);
    return box;
  }
  checkbox('show-forces', S.show.forces && S.has_contact_model,
           function (on) { forces_group.visible = on; });
  checkbox('show-ghost', S.show.ghost && has_ghost, function () { setTime(current_t); });
  checkbox('show-frames', S.show.frames,
           function (on) { frame_axes.forEach(function (a) { a.visible = on; }); });
  checkbox('show-axes', true, function (on) { world_axes.visible = on; });
  document.getElementById('show-forces').disabled = !S.has_contact_model;
  document.getElementById('show-ghost').disabled = !has_ghost;
  controls.addEventListener('change', function () { needs_render = true; });

  // ---------------------------------------------------------------- legend
  function legendRow(html) {
    var row = document.createElement('div');
    row.className = 'row';
    row.innerHTML = html;
    document.getElementById('legend').appendChild(row);
  }
  function escapeHtml(s) {
    return String(s).replace(/[&<>"]/g, function (c) {
      return {'&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;'}[c];
    });
  }
  function hex(c) { return '#' + ('000000' + c.toString(16)).slice(-6); }
  function makeLegend() {
    S.models.forEach(function (m) {
      legendRow('<span class="swatch" style="background:' + m.color + '"></span>' +
                escapeHtml(m.name));
    });
    if (has_ghost) {
      legendRow('<span class="swatch" style="background:#9aa4b1;opacity:0.5"></span>' +
                'ghost: the plan in force');
    }
    if (!S.has_contact_model) return;
    var arrow = function (c, o) {
      return '<span class="arrow" style="background:' + hex(c) + ';opacity:' + o + '"></span>';
    };
    legendRow(arrow(COLORS.normal, 1) + 'normal force' + arrow(COLORS.friction, 1) + 'friction');
    legendRow(arrow(COLORS.normal_distance, 0.55) + arrow(COLORS.friction_distance, 0.55) +
              'pale, hollow point: force at a distance (&phi; &gt; 0)');
    legendRow('<span class="swatch" style="background:#7f0000"></span>' +
              'solid point: penetration (&phi; &le; 0)');
    var length = niceStep(0.25 * R);
    var newtons = length / S.force_scale;
    legendRow('<span class="arrow" style="background:#555;width:44px"></span>' +
              (length * 100).toPrecision(3).replace(/\.?0+$/, '') + ' cm = ' +
              newtons.toPrecision(3) + ' N (largest: ' + S.max_force.toPrecision(3) + ' N)');
  }
  makeLegend();

  // ---------------------------------------------------------------- loop
  function resize() {
    var w = Math.max(view.clientWidth, 1);
    var h = Math.max(view.clientHeight, 1);
    renderer.setSize(w, h);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    needs_render = true;
  }
  window.addEventListener('resize', resize);
  resize();
  function render() {
    renderer.render(scene, camera);
    needs_render = false;
  }
  function tick(ms) {
    window.requestAnimationFrame(tick);
    if (playing) {
      if (last_ms !== null) {
        var t = current_t + (ms - last_ms) / 1000 * speed;
        setTime(t > T1 ? T0 + (t - T1) % Math.max(T1 - T0, 1e-9) : t);
      }
      last_ms = ms;
    }
    if (needs_render) render();
  }

  // ---------------------------------------------------------------- test hook
  function bodyIndex(name) {
    for (var b = 0; b < S.bodies.length; ++b) if (S.bodies[b].name === name) return b;
    throw new Error('idtoViewer: no body named ' + name);
  }
  window.idtoViewer = {
    setTime: function (t) { setPlaying(false); setTime(t); render(); },
    time: function () { return current_t; },
    times: S.times,
    setPlaying: setPlaying,
    bodyPosition: function (name) { return body_groups[bodyIndex(name)].position.toArray(); },
    bodyQuaternion: function (name) {
      return body_groups[bodyIndex(name)].quaternion.toArray();
    },
    ghostPosition: function (name) {
      var g = ghost_groups[bodyIndex(name)];
      return g && g.visible ? g.position.toArray() : null;
    },
    // Contacts drawn at the current frame (0 when the forces overlay is off).
    visibleContacts: function () { return forces_group.visible ? shown_contacts : 0; },
    contactData: function () { return S.contacts[current_frame]; },
    render: render,
    renderer: renderer
  };
  // The test driver (#idto-test=<JSON>): {times: [t...], bodies: [name...], benchmark: n}.
  // For each time: the time label, positions of the named bodies and their ghosts, the number
  // of contacts drawn, and pixel statistics of the canvas (luminance mean and variance, the
  // number of pixels that differ from the first sample's); then the mean milliseconds, over n
  // frames, to move the scene to a time (ms_per_update), to also issue its rendering (the page's
  // main-thread work, ms_per_submit) and to also wait for the pixels (ms_per_frame), with the
  // draw calls and triangles of a frame; the resources the page loaded and the errors it caught.
  window.idtoRunTests = function (cmd) {
    var gl = renderer.getContext();
    var w = gl.drawingBufferWidth;
    var h = gl.drawingBufferHeight;
    var report = {num_frames: N, t0: T0, t1: T1, width: w, height: h, samples: []};
    var first = null;
    (cmd.times || []).forEach(function (t) {
      window.idtoViewer.setTime(t);
      var sample = {t: current_t, label: time_label.textContent, bodies: {}, ghost: {},
                    contacts: window.idtoViewer.visibleContacts()};
      (cmd.bodies || []).forEach(function (name) {
        sample.bodies[name] = window.idtoViewer.bodyPosition(name);
        sample.ghost[name] = window.idtoViewer.ghostPosition(name);
      });
      var px = new Uint8Array(w * h * 4);
      gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
      var sum = 0, sum2 = 0, changed = 0;
      for (var i = 0; i < px.length; i += 4) {
        var y = 0.299 * px[i] + 0.587 * px[i + 1] + 0.114 * px[i + 2];
        sum += y;
        sum2 += y * y;
        if (first && (Math.abs(px[i] - first[i]) > 8 || Math.abs(px[i + 1] - first[i + 1]) > 8 ||
                      Math.abs(px[i + 2] - first[i + 2]) > 8)) {
          ++changed;
        }
      }
      var n = px.length / 4;
      sample.pixels = {mean: sum / n, variance: sum2 / n - (sum / n) * (sum / n),
                       changed_from_first: changed};
      if (!first) first = px;
      report.samples.push(sample);
    });
    if (cmd.benchmark) {
      var one = new Uint8Array(4);
      var start = performance.now();
      for (var u = 0; u < cmd.benchmark; ++u) setTime(T0 + (T1 - T0) * u / cmd.benchmark);
      report.ms_per_update = (performance.now() - start) / cmd.benchmark;
      start = performance.now();
      for (var r = 0; r < cmd.benchmark; ++r) {
        setTime(T0 + (T1 - T0) * r / cmd.benchmark);
        render();
      }
      report.ms_per_submit = (performance.now() - start) / cmd.benchmark;
      report.draw_calls = renderer.info.render.calls;
      report.triangles = renderer.info.render.triangles;
      start = performance.now();
      for (var k = 0; k < cmd.benchmark; ++k) {
        setTime(T0 + (T1 - T0) * k / cmd.benchmark);
        render();
        gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, one);  // waits for the frame
      }
      report.ms_per_frame = (performance.now() - start) / cmd.benchmark;
    }
    report.resources = performance.getEntriesByType('resource').map(function (e) {
      return e.name;
    });
    report.errors = window.idtoErrors;
    document.getElementById('idto-test-output').textContent = JSON.stringify(report);
  };
  let hash = window.location.hash;
  if (hash.indexOf('#idto-test=') === 0) {
    window.idtoRunTests(JSON.parse(decodeURIComponent(hash.slice('#idto-test='.length))));
  } else if (hash.indexOf('#t=') === 0) {
    setTime(parseFloat(hash.slice(3)) || T0);
    render();
    window.requestAnimationFrame(tick);
  } else {
    setTime(T0);
    setPlaying(true);
    window.requestAnimationFrame(tick);
  }
}
