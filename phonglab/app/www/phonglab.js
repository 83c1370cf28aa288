// phonglab's browser-side helpers, loaded by the trame client as a Vue plugin.
//
// <phonglab-colors :push="..."> sits inside a <vtk-local-view>. When the server
// re-shades the mesh it sends only the new colour bytes in `push`
// ({dataset, name, location, data}); this component writes them into the matching
// array of the browser's copy of the scene and re-renders, instead of a full
// scene synchronisation (a JSON delta plus a second round trip for the array).
window.phonglab = {
  install(app) {
    app.component("phonglab-colors", {
      props: { push: { type: Object, default: null } },
      inject: { view: { default: null } },
      data() {
        return { pending: null, tries: 0 };
      },
      mounted() {
        // the local view this component sits in (tests and benchmarks read its camera and pixels)
        window.phonglabView = this.view;
      },
      watch: {
        push(value) {
          this.pending = value;
          this.tries = 0;
          this.apply();
        },
      },
      methods: {
        // the browser's copy of the dataset `dataset` and its array `name` at `location`
        findArray(dataset, name, location) {
          const view = this.view;
          if (!view || !view.ctx) return null;
          const data = view.ctx.getInstance(dataset);
          if (!data || !data.getPointData) return null;
          const fields = location === "cell" ? data.getCellData() : data.getPointData();
          const array = fields.getArrayByName(name);
          return array ? { data, array } : null;
        },
        // The pushed values under the hash trame-vtk gives the server's array. A later full
        // synchronisation of the scene (the end of a drag) then finds them at once: no second
        // download, and vtk.js, seeing the array it already shows, does not rebuild the mesh.
        remember(hash, values) {
          const ctx = this.view && this.view.ctx;
          if (!ctx || !ctx.getArray) return;
          if (!ctx.phonglabPushed) {
            const pushed = (ctx.phonglabPushed = new Map());
            const getArray = ctx.getArray;
            ctx.getArray = (sha, dataType, context) =>
              pushed.has(sha) ? Promise.resolve(pushed.get(sha)) : getArray(sha, dataType, context);
          }
          ctx.phonglabPushed.clear(); // only the newest colours: the older ones are never asked for again
          ctx.phonglabPushed.set(hash, values);
        },
        // tell the server which pushed colours are on screen (it then sends only the rows that change)
        shown(hash) {
          if (window.trame && window.trame.state) window.trame.state.set("view_colors_shown", hash);
        },
        // the bytes of a msgpack binary value (ArrayBuffer or a view into the message)
        bytesOf(raw) {
          return raw instanceof ArrayBuffer ? new Uint8Array(raw) : new Uint8Array(raw.buffer, raw.byteOffset, raw.byteLength);
        },
        // a whole array: a new typed array (never overwrite: the old one may be cached by hash)
        whole(push, old) {
          const bytes = this.bytesOf(push.data);
          // a size mismatch means the geometry changed: the full sync brings the colours
          if (bytes.byteLength !== old.byteLength) return null;
          const values = new old.constructor(old.length);
          new Uint8Array(values.buffer).set(bytes);
          return values;
        },
        // a change from the push `base`: its colours with the rows `rows` replaced by `values`;
        // null when the colours shown are not that push's (the next full sync brings them)
        changed(push, old) {
          const pushed = this.view.ctx && this.view.ctx.phonglabPushed;
          if (!pushed || pushed.get(push.base) !== old) return null;
          const rows = new Uint32Array(this.bytesOf(push.rows).slice().buffer);
          const changed = this.bytesOf(push.values);
          const values = new old.constructor(old.length);
          values.set(old);
          const bytes = new Uint8Array(values.buffer);
          const width = changed.byteLength / Math.max(rows.length, 1);
          if (!Number.isInteger(width) || rows.length * width > bytes.byteLength) return null;
          for (let i = 0; i < rows.length; i++) {
            bytes.set(changed.subarray(i * width, (i + 1) * width), rows[i] * width);
          }
          return values;
        },
        apply() {
          const push = this.pending;
          if (!push || !(push.data || push.rows)) return;
          const found = this.findArray(push.dataset, push.name, push.location);
          if (!found) {
            // the first scene may still be on its way: try again next frame
            if (this.tries++ < 120) requestAnimationFrame(() => this.apply());
            return;
          }
          const old = found.array.getData();
          const values = push.rows ? this.changed(push, old) : this.whole(push, old);
          if (!values) {
            this.pending = null;
            this.shown(null); // the server sends the next colours whole
            return;
          }
          found.array.setData(values, found.array.getNumberOfComponents());
          found.data.modified();
          if (push.hash) this.remember(push.hash, values);
          this.shown(push.hash || null);
          this.pending = null;
          // draw now rather than on the view's next debounced render
          if (this.view.renderer) this.view.renderer.resetCameraClippingRange();
          this.view.renderWindow.render();
          // the re-shaded colours are on screen (phonglab bench ui times a turn to this moment)
          window.dispatchEvent(new CustomEvent("phonglab-colors-applied"));
        },
      },
      template: "<div style='display:none'></div>",
    });

    // <phonglab-letters :tips="..."> sits inside a <vtk-local-view>: the letters N, L, R, V, H
    // at the arrow tips ({letter, base, tip, color}, world coordinates). Each frame in which the
    // browser's camera or the canvas changed, the tips are projected with the browser's own
    // camera; a letter goes just past its tip along the arrow (above it for an arrow seen
    // end-on, like V), and a letter that would cover another one is moved aside.
    const LETTER_GAP = 11; // pixels from the tip to the letter's centre
    const LETTER_BOX = 17; // pixels a letter keeps free around its centre
    app.component("phonglab-letters", {
      props: { tips: { type: Array, default: () => [] }, hidden: { type: Boolean, default: false } },
      inject: { view: { default: null } },
      mounted() {
        const host = this.$el.closest(".phonglab-view") || this.$el.parentNode;
        this.host = host;
        this.layer = document.createElement("div");
        this.layer.className = "phonglab-letters";
        host.appendChild(this.layer);
        this.seen = "";
        this.loop = requestAnimationFrame(() => this.tick());
      },
      beforeUnmount() {
        cancelAnimationFrame(this.loop);
        if (this.layer) this.layer.remove();
      },
      watch: {
        tips() { this.seen = ""; },
        hidden() { this.seen = ""; },
      },
      methods: {
        tick() {
          this.loop = requestAnimationFrame(() => this.tick());
          const view = this.view;
          const renderer = view && view.renderer;
          const canvas = this.host.querySelector("canvas");
          if (!renderer || !canvas) return;
          const camera = renderer.getActiveCamera();
          const key = `${camera.getMTime()} ${canvas.clientWidth} ${canvas.clientHeight} ${canvas.offsetLeft} ${canvas.offsetTop}`;
          if (key === this.seen) return;
          this.seen = key;
          this.draw(renderer, canvas);
        },
        draw(renderer, canvas) {
          const layer = this.layer;
          layer.style.display = this.hidden ? "none" : "";
          const w = canvas.clientWidth, h = canvas.clientHeight;
          if (this.hidden || !w || !h) return;
          const aspect = w / h;
          const screen = (p) => {
            const d = renderer.worldToNormalizedDisplay(p[0], p[1], p[2], aspect);
            return [canvas.offsetLeft + d[0] * w, canvas.offsetTop + (1 - d[1]) * h];
          };
          const placed = [];
          for (const t of this.tips || []) {
            const base = screen(t.base), tip = screen(t.tip);
            let dx = tip[0] - base[0], dy = tip[1] - base[1];
            const length = Math.hypot(dx, dy);
            if (length < 4) { dx = 0; dy = -1; } else { dx /= length; dy /= length; }
            const label = { t, x: tip[0] + dx * LETTER_GAP, y: tip[1] + dy * LETTER_GAP };
            // nearly coinciding arrows: step the letter on past the one it would cover
            for (let tries = 0; tries < 8; tries++) {
              const clash = placed.find((o) => Math.abs(o.x - label.x) < LETTER_BOX && Math.abs(o.y - label.y) < LETTER_BOX);
              if (!clash) break;
              label.x = clash.x + LETTER_BOX;
            }
            placed.push(label);
          }
          while (layer.children.length > placed.length) layer.lastChild.remove();
          placed.forEach((label, i) => {
            let span = layer.children[i];
            if (!span) { span = document.createElement("span"); span.className = "phonglab-letter"; layer.appendChild(span); }
            span.textContent = label.t.letter;
            span.dataset.letter = label.t.letter;
            span.style.color = label.t.color;
            span.style.left = `${label.x.toFixed(1)}px`;
            span.style.top = `${label.y.toFixed(1)}px`;
          });
        },
      },
      template: "<div style='display:none'></div>",
    });
    // <phonglab-address :query="url_query"> writes the server's query of the view into
    // the address bar (history.replaceState) and, once, sends the query the page was
    // opened with to the server (url_request), which checks it and opens that lesson.
    app.component("phonglab-address", {
      props: { query: { type: String, default: "" } },
      mounted() {
        const asked = window.location.search;
        if (asked && window.trame && window.trame.state) window.trame.state.set("url_request", asked);
        else if (this.query) window.history.replaceState(null, "", window.location.pathname + this.query);
      },
      watch: {
        query(value) {
          if (value && value !== window.location.search) {
            window.history.replaceState(null, "", window.location.pathname + value + window.location.hash);
          }
        },
      },
      template: "<div style='display:none'></div>",
    });
    // <phonglab-download :file="..."> saves each new {name, url, serial} the server
    // sends as a download in this browser (an <a download> clicked once).
    app.component("phonglab-download", {
      props: { file: { type: Object, default: null } },
      watch: {
        file(value) {
          if (!value || !value.url) return;
          const link = document.createElement("a");
          link.href = value.url;
          link.download = value.name || "phonglab.png";
          link.style.display = "none";
          document.body.appendChild(link);
          link.click();
          link.remove();
        },
      },
      template: "<div style='display:none'></div>",
    });
  },
};

// A drag that turns the view ends with a click event too; only a click that
// did not move may pick the probe. Capturing listeners on the document run
// before the view's own click handler and stop a moved click there.
(function () {
  let down = null;
  const inView = (event) => event.target && event.target.closest && event.target.closest(".phonglab-view");
  document.addEventListener("pointerdown", (event) => {
    down = inView(event) ? [event.clientX, event.clientY] : null;
  }, true);
  document.addEventListener("click", (event) => {
    if (!down || !inView(event)) return;
    const moved = Math.hypot(event.clientX - down[0], event.clientY - down[1]);
    down = null;
    if (moved > 4) event.stopPropagation();
  }, true);
})();

// Display formulas (.math-block) live in a narrow text column. One wider than
// its column is scaled down to fit, but not below MIN_SCALE of its size (the
// indices would become unreadable); what is still too wide scrolls sideways
// within its block, with a fade at the edge where more of it is hidden.
(function () {
  const MIN_SCALE = 0.8;

  function fit(block) {
    const math = block.querySelector(":scope > math");
    if (!math) return;
    block.style.removeProperty("--math-scale");
    const room = block.clientWidth;
    let natural = math.scrollWidth;
    if (!room || !natural) return;
    let scale = 1;
    // MathML does not scale exactly with the font size: correct twice at most
    for (let i = 0; i < 3 && natural > room && scale > MIN_SCALE; i++) {
      scale = Math.max(MIN_SCALE, scale * room / natural);
      block.style.setProperty("--math-scale", scale.toFixed(4));
      natural = math.scrollWidth;
    }
    edges(block);
  }

  // fades on the sides where part of the formula is scrolled out of sight
  function edges(block) {
    const hidden = block.scrollWidth - block.clientWidth;
    block.classList.toggle("math-more-right", hidden > 1 && block.scrollLeft < hidden - 1);
    block.classList.toggle("math-more-left", hidden > 1 && block.scrollLeft > 1);
  }

  let pending = false;
  function fitAll() {
    if (pending) return;
    pending = true;
    requestAnimationFrame(() => {
      pending = false;
      document.querySelectorAll(".math-block").forEach(fit);
    });
  }

  const holdsFormula = (node) =>
    node.nodeType === 1 && (node.matches(".math-block") || node.querySelector(".math-block"));
  new MutationObserver((records) => {
    if (records.some((r) => Array.from(r.addedNodes).some(holdsFormula))) fitAll();
  }).observe(document.documentElement, { childList: true, subtree: true });
  // the columns change width with the window (and the grid)
  new ResizeObserver(fitAll).observe(document.documentElement);
  window.addEventListener("resize", fitAll);
  document.addEventListener("scroll", (event) => {
    if (event.target.classList && event.target.classList.contains("math-block")) edges(event.target);
  }, true);
  window.phonglabFitMath = fitAll;
})();

// After a server restart the page comes back by itself: when the connection to
// the server closes, a "Reconnecting…" banner shows and the page asks the server
// every second; once it answers, the page reloads and its address (the lesson)
// brings back the same view.
(function () {
  let leaving = false;
  let waiting = false;
  window.addEventListener("beforeunload", () => { leaving = true; });

  function banner() {
    if (document.querySelector(".phonglab-reconnecting")) return;
    const note = document.createElement("div");
    note.className = "phonglab-reconnecting";
    note.setAttribute("role", "status");
    note.textContent = "Connection to the server lost. Reconnecting…";
    document.body.appendChild(note);
  }

  function poll() {
    fetch(window.location.pathname, { cache: "no-store" })
      .then((answer) => { if (answer.ok) window.location.reload(); else setTimeout(poll, 1000); })
      .catch(() => setTimeout(poll, 1000));
  }

  function lost() {
    if (leaving || waiting) return;
    waiting = true;
    banner();
    setTimeout(poll, 1000);
  }

  // trame's client made its connection before this script loaded: subscribe to its closing
  function subscribe() {
    const client = window.trame && window.trame.client;
    if (client && typeof client.onConnectionClose === "function") client.onConnectionClose(lost);
    else setTimeout(subscribe, 500);
  }
  subscribe();
})();
