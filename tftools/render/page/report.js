// tfx report: draws each recording's timelines with uPlot from the JSON in its section, one time axis
// per recording (zooming one plot zooms them all), and links findings, tree and timelines.
// window.tfxReport.sections[i] offers zoom(min, max), reset() and focus(finding) to scripts and tests.
(function () {
  "use strict";
  var COLOURS = {
    rate: "#1f77b4",
    delay: "#9467bd",
    delayMax: "#c9b3e0",
    samples: "#9aa5b1",
    gap: "rgba(230, 126, 0, 0.16)",
    reparenting: "#8e44ad",
    error: "rgba(214, 39, 40, 0.14)",
    warning: "rgba(230, 126, 0, 0.14)",
    info: "rgba(107, 107, 107, 0.10)",
    onArrival: "#2e8b57",
    later: "#e67e00",
    lost: "#d62728",
    undecided: "#b0b0b0",
    wait: "#333333",
  };
  var EDGE_HEIGHT = 120;
  // The tree is drawn at Graphviz's size (labels of 9 to 12 pt), shrunk to fit its box down to this
  // scale (the Nav2 TurtleBot 4's 34 frames fit 1400 px), and scrolled beyond it.
  var TREE_MIN_SCALE = 0.6;
  var STREAM_HEIGHT = 110;
  var report = { sections: [] };
  window.tfxReport = report;

  function axisTimes(axis) {
    var xs = new Array(axis.count);
    for (var i = 0; i < axis.count; i++) xs[i] = axis.start + (i + 0.5) * axis.step;
    return xs;
  }

  function seconds(u, value) {
    return value == null ? "--" : value.toFixed(3) + " s";
  }

  function plotWidth(element) {
    return Math.max(element.clientWidth, 300);
  }

  // An axis as wide as its longest label: uPlot's fixed sizes cut "10 Hz" to "0 Hz" and "0.01 ms" to "0.01 m".
  function axisSize(u, values, axisIdx, cycleNum) {
    var axis = u.axes[axisIdx];
    if (cycleNum > 1) return axis._size; // uPlot asks again while the ticks settle: keep the first answer
    var longest = 0;
    if (values) {
      u.ctx.font = axis.font[0];
      values.forEach(function (v) { longest = Math.max(longest, u.ctx.measureText(String(v)).width); });
    }
    return Math.ceil(axis.ticks.size + axis.gap + longest / (window.devicePixelRatio || 1)) + 4;
  }

  // uPlot breaks a line at every empty bin: an edge at 10 Hz on 20 ms bins would be dots, never a line.
  // Its lines break only across the edge's real gaps (``gaps``, seconds), which are shaded.
  function breaksAt(gaps) {
    return function (u, seriesIdx, idx0, idx1, nullGaps) {
      var shaded = gaps.map(function (g) { return [u.valToPos(g[0], "x", true), u.valToPos(g[1], "x", true)]; });
      return nullGaps.filter(function (n) {
        return shaded.some(function (s) { return n[0] < s[1] && n[1] > s[0]; });
      });
    };
  }

  // A band [from, to] (seconds) across the plotting area, at least 2 px wide.
  function band(u, from, to, colour) {
    var ctx = u.ctx;
    var left = u.valToPos(from, "x", true);
    var right = u.valToPos(to, "x", true);
    var top = u.bbox.top;
    ctx.fillStyle = colour;
    ctx.fillRect(left, top, Math.max(right - left, 2), u.bbox.height);
  }

  function Section(element, data) {
    var self = this;
    this.element = element;
    this.data = data;
    this.plots = [];
    this.active = -1;
    this.xs = axisTimes(data.axis);
    this.full = [data.axis.start, data.axis.start + data.axis.count * data.axis.step];
    var syncing = false;
    this.sync = function (u, key) {
      if (key !== "x" || syncing) return;
      syncing = true;
      var min = u.scales.x.min;
      var max = u.scales.x.max;
      self.plots.forEach(function (other) {
        if (other !== u) other.setScale("x", { min: min, max: max });
      });
      syncing = false;
    };
    element.querySelectorAll(".row.edge").forEach(function (row) {
      self.plots.push(self.edgePlot(row, data.edges[Number(row.dataset.row)], Number(row.dataset.row)));
    });
    element.querySelectorAll(".row.stream").forEach(function (row) {
      self.plots.push(self.streamPlot(row, data.streams[Number(row.dataset.stream)]));
    });
    element.querySelectorAll(".finding").forEach(function (item) {
      var index = Number(item.dataset.finding);
      item.addEventListener("click", function () { self.focus(index); });
      item.addEventListener("keydown", function (event) {
        if (event.key === "Enter" || event.key === " ") self.focus(index);
      });
    });
    var reset = element.querySelector("button.reset");
    if (reset) reset.addEventListener("click", function () { self.reset(); });
    data.edges.forEach(function (edge, row) {
      var drawn = edge.svg && document.getElementById(edge.svg);
      if (drawn) drawn.addEventListener("click", function () { self.show(row); });
    });
  }

  Section.prototype.options = function (row, height, series, axes, scales, draw) {
    return {
      width: plotWidth(row.querySelector(".plot")),
      height: height,
      cursor: { sync: { key: this.data.anchor }, drag: { x: true, y: false } },
      scales: Object.assign({ x: { time: false } }, scales),
      axes: [{ size: 30, values: function (u, ticks) { return ticks.map(function (t) { return t + " s"; }); } }].concat(
        axes.map(function (axis) { return Object.assign({ size: axisSize }, axis); })
      ),
      series: [{ label: "time", value: seconds }].concat(series),
      hooks: { setScale: [this.sync], drawClear: [draw.under], draw: [draw.over] },
    };
  };

  // Each error's and warning's time on the rows it is about: over the edge's gaps within its span where it
  // has some (two 2 s gaps, not the 46 s between their starts), else the span. Notes draw nothing, as in
  // the tree: the legend names red and orange only.
  Section.prototype.findingBands = function (u, row, gaps) {
    var self = this;
    this.data.findings.forEach(function (finding, index) {
      if (finding.from == null || finding.severity === "info" || finding.rows.indexOf(row) < 0) return;
      var colour = COLOURS[finding.severity];
      var inside = gaps.filter(function (g) { return g[1] >= finding.from && g[0] <= finding.to; });
      var spans = inside.length ? inside : [[finding.from, finding.to]];
      spans.forEach(function (span) {
        band(u, span[0], span[1], colour);
        if (index === self.active) band(u, span[0], span[1], colour);
      });
    });
  };

  Section.prototype.edgePlot = function (row, edge, index) {
    var self = this;
    var draw = {
      under: function (u) {
        edge.gaps.forEach(function (gap) { band(u, gap[0], gap[1], COLOURS.gap); });
        self.findingBands(u, index, edge.gaps);
      },
      over: function (u) {
        var ctx = u.ctx;
        var bottom = u.bbox.top + u.bbox.height;
        ctx.fillStyle = COLOURS.samples;
        edge.samples.forEach(function (n, i) {
          if (n > 0) ctx.fillRect(u.valToPos(self.xs[i], "x", true) - 0.5, bottom - 5, 1, 5);
        });
        ctx.strokeStyle = COLOURS.reparenting;
        ctx.lineWidth = 2;
        edge.reparentings.forEach(function (change) {
          var x = u.valToPos(change[0], "x", true);
          ctx.beginPath();
          ctx.moveTo(x, u.bbox.top);
          ctx.lineTo(x, bottom);
          ctx.stroke();
        });
      },
    };
    var gaps = breaksAt(edge.gaps);
    var series = [
      { label: "rate", scale: "hz", stroke: COLOURS.rate, width: 1.5, gaps: gaps, value: function (u, v) { return v == null ? "--" : v.toFixed(1) + " Hz"; } },
      { label: "delay", scale: "ms", stroke: COLOURS.delay, width: 1, gaps: gaps, value: function (u, v) { return v == null ? "--" : v.toFixed(2) + " ms"; } },
      { label: "max delay", scale: "ms", stroke: COLOURS.delayMax, width: 1, dash: [4, 3], gaps: gaps, value: function (u, v) { return v == null ? "--" : v.toFixed(2) + " ms"; } },
      { label: "samples", show: false, value: function (u, v) { return v == null ? "--" : String(v); } },
    ];
    var axes = [
      { scale: "hz", values: function (u, ticks) { return ticks.map(function (t) { return t + " Hz"; }); } },
      { scale: "ms", side: 1, grid: { show: false }, stroke: COLOURS.delay, values: function (u, ticks) { return ticks.map(function (t) { return t + " ms"; }); } },
    ];
    var scales = {
      // the rate line near the top, the delay's around the middle: apart where both are steady
      hz: { range: function (u, min, max) { return [0, Math.max((max || 0) * 1.2, 1)]; } },
      ms: { range: function (u, min, max) { return [0, Math.max((max || 0) * 1.8, 0.01)]; } },
    };
    var values = [this.xs, edge.rate, edge.delayMean, edge.delayMax, edge.samples];
    if (!this.data.delays) { // the recording's clocks give no delays: no delay lines, no empty axis for them
      series.splice(1, 2);
      axes.splice(1, 1);
      values.splice(2, 2);
    }
    return new uPlot(this.options(row, EDGE_HEIGHT, series, axes, scales, draw), values, row.querySelector(".plot"));
  };

  Section.prototype.streamPlot = function (row, stream) {
    var self = this;
    var names = ["undecided", "lost", "later", "on_arrival"];
    var colours = [COLOURS.undecided, COLOURS.lost, COLOURS.later, COLOURS.onArrival];
    var labels = ["undecided", "lost", "later", "on arrival"];
    // Stacked: each series is the sum of itself and those drawn after it, so that later ones cover the bottom.
    var stacked = names.map(function (name, k) {
      return self.xs.map(function (_, i) {
        var total = 0;
        for (var j = k; j < names.length; j++) total += stream.fates[names[j]][i];
        return total || null;
      });
    });
    var bars = uPlot.paths.bars({ size: [1, Infinity], gap: 0 });
    var series = names.map(function (name, k) {
      return {
        label: labels[k],
        scale: "n",
        fill: colours[k],
        stroke: colours[k],
        width: 0,
        paths: bars,
        points: { show: false },
        value: function (u, v, s, i) { return i == null ? "--" : String(stream.fates[name][i]); },
      };
    });
    series.push({ label: "longest wait", scale: "s", stroke: COLOURS.wait, width: 1, value: function (u, v) { return v == null ? "--" : v.toFixed(3) + " s"; } });
    var axes = [
      { scale: "n" },
      { scale: "s", side: 1, grid: { show: false }, values: function (u, ticks) { return ticks.map(function (t) { return t + " s"; }); } },
    ];
    var scales = {
      n: { range: function (u, min, max) { return [0, Math.max((max || 0) * 1.1, 1)]; } },
      s: { range: function (u, min, max) { return [0, Math.max((max || 0) * 1.15, 0.01)]; } },
    };
    var draw = { under: function () {}, over: function () {} };
    var values = [this.xs].concat(stacked, [stream.waitMax]);
    return new uPlot(this.options(row, STREAM_HEIGHT, series, axes, scales, draw), values, row.querySelector(".plot"));
  };

  Section.prototype.zoom = function (min, max) {
    if (this.plots.length) this.plots[0].setScale("x", { min: min, max: max });
  };

  Section.prototype.reset = function () {
    this.zoom(this.full[0], this.full[1]);
  };

  // A finding chosen: its item, edges and timeline rows marked, every timeline zoomed to its time.
  Section.prototype.focus = function (index) {
    var finding = this.data.findings[index];
    this.active = index;
    this.element.querySelectorAll(".finding").forEach(function (item) {
      item.classList.toggle("active", Number(item.dataset.finding) === index);
    });
    this.element.querySelectorAll(".row.edge").forEach(function (row) {
      row.classList.toggle("active", finding.rows.indexOf(Number(row.dataset.row)) >= 0);
    });
    this.element.querySelectorAll(".tree .active").forEach(function (drawn) { drawn.classList.remove("active"); });
    finding.svg.forEach(function (id) {
      var drawn = document.getElementById(id);
      if (drawn) drawn.classList.add("active");
    });
    if (finding.from != null) {
      var pad = Math.max((finding.to - finding.from) * 0.25, this.data.axis.step * 20, 0.5);
      this.zoom(finding.from - pad, finding.to + pad);
    }
    this.plots.forEach(function (u) { u.redraw(false); });
  };

  // An edge chosen in the tree: its timeline brought into view.
  Section.prototype.show = function (row) {
    var element = this.element.querySelector('.row.edge[data-row="' + row + '"]');
    if (!element) return;
    element.scrollIntoView({ block: "center" });
    element.classList.remove("flash");
    void element.offsetWidth;
    element.classList.add("flash");
  };

  Section.prototype.resize = function () {
    this.plots.forEach(function (u) {
      u.setSize({ width: plotWidth(u.root.parentElement), height: u.height });
    });
  };

  function fitTrees() {
    document.querySelectorAll(".tree svg").forEach(function (svg) {
      var natural = Number(svg.dataset.width) || svg.width.baseVal.value;
      svg.dataset.width = String(natural);
      var box = svg.parentElement;
      var room = box.clientWidth - 12;
      var scale = Math.max(Math.min(1, room / natural), TREE_MIN_SCALE);
      svg.style.width = Math.floor(natural * scale) + "px";
    });
  }

  fitTrees();
  document.querySelectorAll("section.recording").forEach(function (element) {
    var script = element.querySelector("script.report-data");
    if (script) report.sections.push(new Section(element, JSON.parse(script.textContent)));
  });
  window.addEventListener("resize", function () {
    fitTrees();
    report.sections.forEach(function (section) { section.resize(); });
  });
})();
