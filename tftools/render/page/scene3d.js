// tfx report's 3D view: every frame of a recording as an axis triad (x red, y green, z blue) in the fixed
// frame, drawn with three.js from the poses in the section's JSON (data.scene3d), at the time the slider
// chooses; names on hover; drag to orbit, shift-drag to pan, scroll to zoom; a click on a finding shows
// its frames at its time. window.tfxScene3d.views[i] offers setTime(index), timeIndex(seconds),
// positions(), axes(), screen() and focus(finding) to scripts and tests.
(function () {
  "use strict";
  var HEIGHT = 520;
  // Frames whose names are shown at once by default (more: on hover, on a finding, or with "names"): the
  // 34 of the Nav2 TurtleBot 4, most within 30 cm, made one blob of text.
  var NAMES_SHOWN = 12;
  var GRID_LINES = 20; // the floor grid's cells along a side
  var AXIS_COLOURS = [0xd62728, 0x2ca02c, 0x1f5fd6];
  var LINK_COLOUR = 0x8a8a8a;
  var FOCUS_COLOUR = "#d62728";
  var registry = { views: [] };
  window.tfxScene3d = registry;

  function poseAt(frame, index) {
    if (frame.pose) return frame.pose;
    return frame.poses[index];
  }

  // A triad, as RViz draws axes: a bar from the origin along x, y and z, each in its colour.
  function triad(size) {
    var group = new THREE.Group();
    var radius = size * 0.06;
    for (var axis = 0; axis < 3; axis++) {
      var bar = new THREE.Mesh(
        new THREE.CylinderGeometry(radius, radius, size, 10),
        new THREE.MeshBasicMaterial({ color: AXIS_COLOURS[axis] })
      );
      // a cylinder stands along y, centred: turned onto its axis, moved to start at the origin
      if (axis === 0) bar.rotation.z = -Math.PI / 2;
      if (axis === 2) bar.rotation.x = Math.PI / 2;
      bar.position.setComponent(axis, size / 2);
      group.add(bar);
    }
    return group;
  }

  function View(section, element, data) {
    var self = this;
    this.section = section;
    this.element = element;
    this.data = data;
    this.index = 0;
    this.focused = [];
    this.frames = data.frames;
    this.byName = {};
    data.frames.forEach(function (frame, k) { self.byName[frame.name] = k; });

    var controls = document.createElement("div");
    controls.className = "scene3d-controls";
    this.slider = document.createElement("input");
    this.slider.type = "range";
    this.slider.min = "0";
    this.slider.max = String(data.times.length - 1);
    this.slider.value = "0";
    this.slider.setAttribute("aria-label", "time");
    this.clock = document.createElement("span");
    this.clock.className = "scene3d-time";
    var play = document.createElement("button");
    play.type = "button";
    play.textContent = "Play";
    var names = document.createElement("label");
    names.innerHTML = '<input type="checkbox"> names';
    names.firstChild.checked = data.frames.length <= NAMES_SHOWN;
    this.showNames = names.firstChild.checked;
    controls.appendChild(play);
    controls.appendChild(names);
    controls.appendChild(this.slider);
    controls.appendChild(this.clock);
    var stage = document.createElement("div");
    stage.className = "scene3d-stage";
    stage.style.position = "relative";
    this.tip = document.createElement("div");
    this.tip.className = "scene3d-tip";
    this.tip.style.cssText = "position:absolute;pointer-events:none;display:none;background:rgba(255,255,255,0.92);" +
      "border:1px solid #999;padding:2px 5px;font:12px monospace;white-space:nowrap;";
    this.labels = document.createElement("div");
    this.labels.style.cssText = "position:absolute;left:0;top:0;pointer-events:none;";
    element.appendChild(controls);
    element.appendChild(stage);

    this.width = Math.max(element.clientWidth, 320);
    try {
      this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    } catch (e) {
      this.renderer = null;
      var none = document.createElement("p");
      none.className = "missing";
      none.textContent = "This browser cannot draw in 3D (WebGL is unavailable): " + e;
      stage.appendChild(none);
    }
    if (this.renderer) {
      this.renderer.setPixelRatio(window.devicePixelRatio || 1);
      this.renderer.setSize(this.width, HEIGHT);
      this.renderer.setClearColor(0xffffff, 1);
      stage.appendChild(this.renderer.domElement);
    }
    stage.appendChild(this.labels);
    stage.appendChild(this.tip);
    this.stage = stage;

    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(45, this.width / HEIGHT, 0.001, 1e6);
    this.camera.up.set(0, 0, 1); // ROS: z up
    this.index = this.fullest();
    var placed = this.placedAt(this.index);
    this.target = median(placed);
    var spread = placed.map(function (p) { return p.distanceTo(self.target); }).sort(function (x, y) { return x - y; });
    // the robot's size: how far most frames lie from their middle (a far map or odom left out)
    this.size = Math.max(spread.length ? spread[Math.floor(spread.length * 0.9)] : 0, 0.3);
    var axisSize = Math.min(Math.max(this.typicalEdge() * 0.45, this.size * 0.08, 0.02), 5);
    this.axisSize = axisSize;
    this.triads = data.frames.map(function (frame) {
      var group = triad(axisSize);
      group.name = frame.name;
      self.scene.add(group);
      return group;
    });
    // The floor: the fixed frame's x-y plane under the robot, in cells of a round size (1, 2 or 5 x 10^k m)
    // about a third of the robot's, so that distances can be read off it.
    var cell = roundStep(this.size / 3);
    var grid = new THREE.GridHelper(cell * GRID_LINES, GRID_LINES, 0x9a9a9a, 0xd0d0d0);
    grid.rotation.x = Math.PI / 2; // in the fixed frame's x-y plane
    grid.position.set(Math.round(this.target.x / cell) * cell, Math.round(this.target.y / cell) * cell, 0);
    this.gridCell = cell;
    this.scene.add(grid);
    this.links = new THREE.LineSegments(
      new THREE.BufferGeometry(),
      new THREE.LineBasicMaterial({ color: LINK_COLOUR, transparent: true, opacity: 0.7 })
    );
    this.scene.add(this.links);

    // the orbit: a target, a distance, and two angles about it (z up)
    this.distance = this.size * 3.6;
    this.azimuth = -Math.PI * 0.7;
    this.elevation = 0.45;
    this.listen(play, names);
    this.placeCamera();
    this.setTime(this.index);
  }

  // The round number (1, 2 or 5 times a power of ten) nearest above ``value``.
  function roundStep(value) {
    var power = Math.pow(10, Math.floor(Math.log10(Math.max(value, 1e-6))));
    var steps = [1, 2, 5, 10];
    for (var i = 0; i < steps.length; i++) if (steps[i] * power >= value) return steps[i] * power;
    return 10 * power;
  }

  function median(points) {
    if (!points.length) return new THREE.Vector3();
    var middle = function (axis) {
      var values = points.map(function (p) { return p.getComponent(axis); }).sort(function (x, y) { return x - y; });
      return values[Math.floor(values.length / 2)];
    };
    return new THREE.Vector3(middle(0), middle(1), middle(2));
  }

  // Where the frames are at time ``index``.
  View.prototype.placedAt = function (index) {
    var found = [];
    this.frames.forEach(function (frame) {
      var p = poseAt(frame, index);
      if (p) found.push(new THREE.Vector3(p[0], p[1], p[2]));
    });
    return found;
  };

  // The usual distance between a frame and its parent (the median of those apart), at the view's time.
  View.prototype.typicalEdge = function () {
    var self = this;
    var lengths = [];
    this.frames.forEach(function (frame) {
      var p = poseAt(frame, self.index);
      var k = self.byName[frame.parent];
      var q = k === undefined ? null : poseAt(self.frames[k], self.index);
      if (p && q) {
        var d = Math.hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]);
        if (d > 1e-6) lengths.push(d);
      }
    });
    lengths.sort(function (x, y) { return x - y; });
    return lengths.length ? lengths[Math.floor(lengths.length / 2)] : 0.1;
  };

  // The first time at which the most frames are placed.
  View.prototype.fullest = function () {
    var best = 0;
    var most = -1;
    for (var i = 0; i < this.data.times.length; i++) {
      var placed = 0;
      for (var k = 0; k < this.frames.length; k++) if (poseAt(this.frames[k], i)) placed++;
      if (placed > most) {
        most = placed;
        best = i;
      }
    }
    return best;
  };

  View.prototype.placeCamera = function () {
    var c = Math.cos(this.elevation);
    this.camera.position.set(
      this.target.x + this.distance * c * Math.cos(this.azimuth),
      this.target.y + this.distance * c * Math.sin(this.azimuth),
      this.target.z + this.distance * Math.sin(this.elevation)
    );
    this.camera.lookAt(this.target);
    this.camera.updateMatrixWorld();
    this.draw();
  };

  View.prototype.listen = function (play, names) {
    var self = this;
    names.firstChild.addEventListener("change", function () {
      self.showNames = names.firstChild.checked;
      self.drawLabels();
    });
    this.slider.addEventListener("input", function () { self.setTime(Number(self.slider.value)); });
    var timer = null;
    play.addEventListener("click", function () {
      if (timer) {
        clearInterval(timer);
        timer = null;
        play.textContent = "Play";
        return;
      }
      play.textContent = "Pause";
      timer = setInterval(function () {
        self.setTime((self.index + 1) % self.data.times.length);
      }, 80);
    });
    var canvas = this.renderer ? this.renderer.domElement : this.stage;
    var dragging = null;
    canvas.addEventListener("pointerdown", function (event) {
      dragging = { x: event.clientX, y: event.clientY, pan: event.shiftKey || event.button === 2 };
      if (canvas.setPointerCapture) canvas.setPointerCapture(event.pointerId);
    });
    canvas.addEventListener("pointerup", function () { dragging = null; });
    canvas.addEventListener("contextmenu", function (event) { event.preventDefault(); });
    canvas.addEventListener("pointermove", function (event) {
      if (!dragging) {
        self.hover(event);
        return;
      }
      var dx = event.clientX - dragging.x;
      var dy = event.clientY - dragging.y;
      dragging.x = event.clientX;
      dragging.y = event.clientY;
      if (dragging.pan) {
        self.pan(dx, dy);
      } else {
        self.azimuth -= dx * 0.01;
        self.elevation = Math.max(-1.55, Math.min(1.55, self.elevation + dy * 0.01));
        self.placeCamera();
      }
    });
    canvas.addEventListener("wheel", function (event) {
      event.preventDefault();
      self.distance = Math.max(self.size * 0.02, Math.min(self.size * 500, self.distance * Math.exp(event.deltaY * 0.001)));
      self.placeCamera();
    }, { passive: false });
    this.section.querySelectorAll(".finding").forEach(function (item) {
      item.addEventListener("click", function () { self.focus(Number(item.dataset.finding)); });
    });
  };

  View.prototype.pan = function (dx, dy) {
    var scale = this.distance / HEIGHT;
    var right = new THREE.Vector3().setFromMatrixColumn(this.camera.matrixWorld, 0);
    var up = new THREE.Vector3().setFromMatrixColumn(this.camera.matrixWorld, 1);
    this.target.addScaledVector(right, -dx * scale).addScaledVector(up, dy * scale);
    this.placeCamera();
  };

  // The slider's time ``index``: every triad where tf2 placed its frame then (hidden where it could not).
  View.prototype.setTime = function (index) {
    var self = this;
    this.index = index;
    this.slider.value = String(index);
    var points = [];
    this.frames.forEach(function (frame, k) {
      var p = poseAt(frame, index);
      var group = self.triads[k];
      group.visible = !!p;
      if (!p) return;
      group.position.set(p[0], p[1], p[2]);
      group.quaternion.set(p[3], p[4], p[5], p[6]);
      var parent = self.byName[frame.parent];
      var q = parent === undefined ? null : poseAt(self.frames[parent], index);
      if (q) points.push(q[0], q[1], q[2], p[0], p[1], p[2]);
    });
    this.links.geometry.dispose();
    var geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", new THREE.Float32BufferAttribute(points, 3));
    this.links.geometry = geometry;
    this.scene.updateMatrixWorld(true);
    this.clock.textContent = " " + this.data.times[index].toFixed(3) + " s (stamp " + this.data.stamps[index] + ")";
    this.draw();
  };

  // The index of the time nearest ``seconds`` (on the timelines' axis).
  View.prototype.timeIndex = function (seconds) {
    var times = this.data.times;
    var best = 0;
    for (var i = 1; i < times.length; i++) {
      if (Math.abs(times[i] - seconds) < Math.abs(times[best] - seconds)) best = i;
    }
    return best;
  };

  View.prototype.draw = function () {
    if (this.renderer) this.renderer.render(this.scene, this.camera);
    this.drawLabels();
  };

  // Where each shown frame's origin is on the canvas (CSS pixels), by name.
  View.prototype.screen = function () {
    var self = this;
    var found = {};
    this.triads.forEach(function (group) {
      if (!group.visible) return;
      var v = group.getWorldPosition(new THREE.Vector3()).project(self.camera);
      if (v.z < -1 || v.z > 1) return;
      found[group.name] = [(v.x + 1) / 2 * self.width, (1 - v.y) / 2 * HEIGHT];
    });
    return found;
  };

  // Each shown frame's origin in the fixed frame, as drawn, by name.
  View.prototype.positions = function () {
    var found = {};
    this.triads.forEach(function (group) {
      if (!group.visible) return;
      var v = group.getWorldPosition(new THREE.Vector3());
      found[group.name] = [v.x, v.y, v.z];
    });
    return found;
  };

  // Each shown frame's axes (unit x, y, z) in the fixed frame, as drawn, by name.
  View.prototype.axes = function () {
    var found = {};
    this.triads.forEach(function (group) {
      if (!group.visible) return;
      var m = group.matrixWorld.elements;
      var k = 1 / group.scale.x; // a focused triad is drawn larger
      found[group.name] = [[m[0] * k, m[1] * k, m[2] * k], [m[4] * k, m[5] * k, m[6] * k], [m[8] * k, m[9] * k, m[10] * k]];
    });
    return found;
  };

  View.prototype.hover = function (event) {
    var box = this.stage.getBoundingClientRect();
    var x = event.clientX - box.left;
    var y = event.clientY - box.top;
    var spots = this.screen();
    var best = null;
    var bestDistance = 12;
    Object.keys(spots).forEach(function (name) {
      var d = Math.hypot(spots[name][0] - x, spots[name][1] - y);
      if (d < bestDistance) {
        best = name;
        bestDistance = d;
      }
    });
    if (!best) {
      this.tip.style.display = "none";
      return;
    }
    var p = poseAt(this.frames[this.byName[best]], this.index);
    this.tip.textContent = best + "  [" + p.slice(0, 3).map(function (v) { return v.toFixed(3); }).join(", ") + "] m";
    this.tip.style.left = spots[best][0] + 10 + "px";
    this.tip.style.top = spots[best][1] + 10 + "px";
    this.tip.style.display = "block";
  };

  // The frames' names beside them (all with "names" ticked), those of a chosen finding in red; frames at
  // one place share a label.
  View.prototype.drawLabels = function () {
    var self = this;
    var spots = this.screen();
    var shown = this.showNames ? Object.keys(spots) : this.focused.filter(function (name) { return spots[name]; });
    var places = {};
    shown.forEach(function (name) {
      var key = Math.round(spots[name][0] / 3) + "," + Math.round(spots[name][1] / 3);
      (places[key] = places[key] || []).push(name);
    });
    this.labels.textContent = "";
    Object.keys(places).forEach(function (key) {
      var names = places[key];
      var at = spots[names[0]];
      var focused = names.some(function (name) { return self.focused.indexOf(name) >= 0; });
      var label = document.createElement("span");
      label.textContent = names.join(", ");
      label.style.cssText = "position:absolute;white-space:nowrap;font:" + (focused ? "bold 13px" : "11px") +
        " monospace;color:" + (focused ? FOCUS_COLOUR : "#444") + ";left:" + (at[0] + 5) + "px;top:" + (at[1] - 15) + "px";
      self.labels.appendChild(label);
    });
  };

  // A finding chosen: its frames marked (larger triads, their names shown) at its time.
  View.prototype.focus = function (index) {
    var self = this;
    var finding = this.section.tfxFindings ? this.section.tfxFindings[index] : null;
    if (!finding) return;
    this.focused = (finding.frames || []).filter(function (name) { return name in self.byName; });
    this.triads.forEach(function (group) {
      var big = self.focused.indexOf(group.name) >= 0;
      group.scale.setScalar(big ? 2.5 : 1);
    });
    if (finding.from != null) this.setTime(this.timeIndex(finding.from));
    else this.setTime(this.index);
  };

  // The page's width changed: the view follows it.
  View.prototype.resize = function () {
    this.width = Math.max(this.element.clientWidth, 320);
    this.camera.aspect = this.width / HEIGHT;
    this.camera.updateProjectionMatrix();
    if (this.renderer) this.renderer.setSize(this.width, HEIGHT);
    this.draw();
  };

  window.addEventListener("resize", function () {
    registry.views.forEach(function (view) { view.resize(); });
  });

  document.querySelectorAll("section.recording").forEach(function (section) {
    var script = section.querySelector("script.report-data");
    var element = section.querySelector(".scene3d");
    if (!script || !element || typeof THREE === "undefined") return;
    var data = JSON.parse(script.textContent);
    if (!data.scene3d) return;
    section.tfxFindings = data.findings;
    registry.views.push(new View(section, element, data.scene3d));
  });
})();
