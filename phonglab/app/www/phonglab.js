// phonglab's browser-side helpers, loaded by the trame client as a Vue plugin.
//
// <phonglab-colors :push="..."> sits inside a <vtk-local-view>. When the server
// re-shades the mesh it sends only the new colour bytes in `push`
// ({dataset, name, location, data}); this component writes them into the matching
// array of the browser's copy of the scene and re-renders, instead of a full
// scene synchronisation (a JSON delta plus a second round trip for the array).
//
// It also decides which frames of a drag are drawn. Each new camera goes to the server, which
// re-shades for it and pushes the colours back (about 50 ms on one machine). With a GPU a frame
// costs milliseconds and the browser draws every camera at once, with the old colours, until the
// new ones come. Where WebGL is drawn in software a frame of a large mesh costs far more than that
// round trip (0.4-0.65 s for 100k vertices on 2 cores): drawing the turned mesh with the old
// colours would put the true frame a whole frame later. So when the frames measured here are
// slower than the colours' round trip (and slower than SLOW_FRAME_MS), a new camera is held, not
// drawn, until its colours arrive or a frame's time has passed; and an animation frame in which
// nothing changed (the button held still) is not drawn at all. The letters wait with the mesh.
// Where the core's picture covers the view (per-pixel mode, a translucent mesh) vtk.js's frames
// are never seen: a drag draws none, and the letters hide until the picture for the new eye comes
// (at most LETTERS_BACK_MS after the drag), rather than float over the old picture's arrows.
const SLOW_FRAME_MS = 50;
const HOLD_MIN_MS = 100, HOLD_MAX_MS = 1000;
const LETTERS_BACK_MS = 5000;
window.phonglab = {
  install(app) {
    app.component("phonglab-colors", {
      props: { push: { type: Object, default: null }, expect: { type: Boolean, default: true },
               picture: { type: String, default: "" } },
      inject: { view: { default: null } },
      data() {
        return { pending: null, tries: 0 };
      },
      mounted() {
        // the local view this component sits in (tests and benchmarks read its camera and pixels)
        window.phonglabView = this.view;
        // the view is on the page (after the lesson opened): the server sends it its camera, which is the
        // scene's with the angle that holds the arrows and markers (one sent before the view was here is lost)
        if (window.trame && typeof window.trame.trigger === "function") window.trame.trigger("phonglab_view_ready");
        // not reactive: the drawing policy's bookkeeping (see the top of this file)
        this.draw = { shown: null, colours: 0, coloursShown: 0, holdSince: null, holdLimit: 0, timer: null,
                      changedAt: null, frameMs: 0, roundTripMs: null, lettersTimer: null };
        if (this.view) this.view.phonglabDraw = this.draw; // read by the browser tests
        // the hash of the pushed colours on screen, and the last one the server was told (see tell())
        this.hashes = { shown: null, told: null };
        if (this.view) this.view.phonglabColours = this.hashes; // read by the browser tests and `bench ui`
        const interactor = this.view && this.view.interactor;
        if (!interactor) return;
        this.subscriptions = [
          interactor.onStartAnimation(() => this.tell()), // a drag or a zoom starts
          interactor.onAnimation(() => this.frame(false)),
          interactor.onEndAnimation(() => this.frame(true)),
          interactor.onRenderEvent(() => this.drawn()),
        ];
      },
      beforeUnmount() {
        (this.subscriptions || []).forEach((s) => s.unsubscribe());
        if (this.draw) {
          clearTimeout(this.draw.timer);
          clearTimeout(this.draw.lettersTimer);
        }
      },
      watch: {
        push(value) {
          this.pending = value;
          this.tries = 0;
          this.apply();
        },
        // the core's picture for the view as it is now: letters back on it (unless a drag goes on)
        picture() {
          const view = this.view;
          if (view && view.phonglabLettersHidden && !(view.interactor && view.interactor.isAnimating())) {
            this.showLetters();
          }
        },
      },
      methods: {
        // what a frame shows: "camera|scene synchronised last|canvas size"
        shownKey() {
          const view = this.view;
          const camera = view.renderer ? view.renderer.getActiveCamera() : null;
          if (!camera) return null;
          const size = view.openglRenderWindow ? view.openglRenderWindow.getSize() : [];
          const eye = [camera.getPosition(), camera.getFocalPoint(), camera.getViewUp(), camera.getViewAngle()];
          return `${eye.join(" ")}|${view.mtime}|${size}`;
        },
        cameraOf(key) {
          return key === null ? null : key.split("|")[0];
        },
        // hold only where a frame costs more than waiting for the colours
        slow() {
          const d = this.draw;
          return d.frameMs > SLOW_FRAME_MS && (d.roundTripMs === null || d.frameMs > d.roundTripMs);
        },
        holdLimit() {
          return Math.min(HOLD_MAX_MS, Math.max(HOLD_MIN_MS, this.draw.frameMs));
        },
        showLetters() {
          clearTimeout(this.draw.lettersTimer);
          this.view.phonglabLettersHidden = false;
        },
        // the core's picture covers the view: nothing of vtk.js's is seen during a drag, and the letters
        // (placed for the browser's camera) would leave the picture's arrows until its next picture
        covered(ending) {
          const view = this.view, interactor = view.interactor, d = this.draw;
          interactor.setEnableRender(false);
          if (ending) queueMicrotask(() => interactor.setEnableRender(true)); // drawn normally again after
          if (this.cameraOf(this.shownKey()) === this.cameraOf(d.shown)) return; // not turned (yet)
          view.phonglabLettersHidden = true;
          clearTimeout(d.lettersTimer);
          d.lettersTimer = setTimeout(() => this.showLetters(), LETTERS_BACK_MS);
        },
        // called by vtk.js before it draws an animation frame (and before the frame after a drag's end)
        frame(ending) {
          const view = this.view, interactor = view.interactor, d = this.draw;
          if (!view.renderer || (view.busy && view.busy.count > 0)) return; // trame is loading a scene: its switch
          if (!this.expect) {
            this.covered(ending);
            return;
          }
          const key = this.shownKey();
          const newCamera = this.cameraOf(key) !== this.cameraOf(d.shown);
          const newColours = d.colours !== d.coloursShown;
          const changed = key !== d.shown || newColours;
          const now = performance.now();
          if (newCamera && d.changedAt === null) d.changedAt = now;
          let draw = changed;
          if (newCamera && !newColours && this.slow()) {
            if (d.holdSince === null) {
              d.holdSince = now;
              d.holdLimit = this.holdLimit(); // fixed for this hold: the timer and this test agree
              d.timer = setTimeout(() => this.release(), d.holdLimit);
            }
            draw = now - d.holdSince >= d.holdLimit;
          }
          view.phonglabHeld = !draw && newCamera;
          interactor.setEnableRender(draw);
          if (!draw && ending && !view.phonglabHeld) {
            // nothing new at the drag's end: skip vtk.js's closing frame, then draw normally again
            queueMicrotask(() => { if (!view.phonglabHeld) interactor.setEnableRender(true); });
          }
        },
        // a held camera is drawn: its colours came, or waiting longer would cost more than a stale
        // frame. When still, it is drawn at once; during a drag by the next animation frame, which
        // finds new colours or a hold as old as its limit (the hold ends when a frame is drawn).
        release() {
          const view = this.view, d = this.draw;
          clearTimeout(d.timer);
          d.timer = null;
          view.phonglabHeld = false;
          if (!(view.busy && view.busy.count > 0)) view.interactor.setEnableRender(true);
          view.renderWindow.render();
        },
        // vtk.js finished a render call: if it drew, remember what is on screen and time the frame
        // (from the draw to the second animation frame after it: the first may come before it is on screen)
        drawn() {
          const view = this.view, d = this.draw;
          if (!view.interactor.getEnableRender()) return;
          d.shown = this.shownKey();
          d.holdSince = null;
          clearTimeout(d.timer);
          d.timer = null;
          view.phonglabHeld = false;
          const freshColours = d.colours !== d.coloursShown;
          d.coloursShown = d.colours;
          const start = performance.now();
          requestAnimationFrame(() => requestAnimationFrame(() => {
            const ms = performance.now() - start;
            d.frameMs = d.frameMs ? 0.7 * d.frameMs + 0.3 * ms : ms;
          }));
          // a frame with new colours was drawn (phonglab bench ui reads its pixels back next frame)
          if (freshColours) window.dispatchEvent(new CustomEvent("phonglab-colors-applied"));
        },
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
        // the pushed colours now on screen (null: none); `turning` says the server must hear of them now
        shown(hash, turning) {
          this.hashes.shown = hash;
          if (turning || (this.view.interactor && this.view.interactor.isAnimating())) this.tell();
        },
        // Tell the server which pushed colours are on screen: a turn's next colours then come as only the
        // rows that change. Only a turn sends changes, so the server hears it when one starts and during
        // one, not after every slider step: a slider's colours come whole, and an answer per step would
        // be a second message for the server to handle each time.
        tell() {
          const h = this.hashes;
          if (!h || h.told === h.shown) return;
          h.told = h.shown;
          if (window.trame && window.trame.state) window.trame.state.set("view_colors_shown", h.shown);
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
            // the server sends the next colours whole (told only if it was told of other colours)
            this.shown(null, this.hashes.told !== null);
            return;
          }
          found.array.setData(values, found.array.getNumberOfComponents());
          found.data.modified();
          if (push.hash) this.remember(push.hash, values);
          this.shown(push.hash || null, !!push.rows); // a change comes during a turn: its next may be one too
          this.pending = null;
          const d = this.draw;
          if (d) {
            d.colours += 1;
            if (d.changedAt !== null) {  // the colours' round trip since the camera changed
              const ms = performance.now() - d.changedAt;
              // (a camera the server refused brings no colours: a later push's wait is not a round trip)
              if (ms < 5000) d.roundTripMs = d.roundTripMs === null ? ms : 0.7 * d.roundTripMs + 0.3 * ms;
              d.changedAt = null;
            }
          }
          // draw now rather than on the view's next debounced render (a held camera with them)
          if (this.view.renderer) this.view.renderer.resetCameraClippingRange();
          if (d) this.release();
          else this.view.renderWindow.render();
        },
      },
      template: "<div style='display:none'></div>",
    });

    // <phonglab-letters :tips="..."> sits inside a <vtk-local-view>: the letters N, L, R, V, H
    // at the arrow tips ({letter, base, tip, color}, world coordinates). Each frame in which the
    // browser's camera or the canvas changed, the tips are projected with the browser's own
    // camera; a letter goes just past its tip along the arrow (above it for an arrow seen
    // end-on, like V). Where that place covers a letter placed before, lies as near another
    // arrow's tip as its own (a letter reads as its nearest tip's) or on another arrow, the letter
    // turns about its own tip, then a ring further out: it never wanders off to another arrow.
    // Arrows whose tips (nearly) meet, N, L and R at lesson 3's probe, share one label, "N, L, R":
    // their letters side by side in their arrows' colours, placed as one wider letter about the
    // tips' middle (render/annotate.label_layout does the same on figures).
    const LETTER_GAP = 11; // pixels from the tip to the letter's centre
    const LETTER_BOX = 17; // pixels a letter keeps free around its centre
    const LETTER_STEP = 7; // pixels from one ring of places about a tip to the next
    const LETTER_RINGS = 3;
    const LETTER_TURNS = [0, 45, -45, 90, -90, 135, -135, 180]; // degrees from the arrow's direction
    const SAME_TIP = 3; // pixels: tips nearer than this are one place (a letter cannot tell them apart)
    const LETTER_TOGETHER = 15; // pixels, the letters' font size: tips nearer than this share one label
    const LETTER_JOIN = ", "; // between the letters of a shared label
    // a vtk.js camera and the server's {position, view_angle}: the same to a millionth
    function sameCamera(camera, server) {
      const a = camera.getPosition(), b = server.position;
      const scale = Math.max(1, Math.hypot(a[0], a[1], a[2]));
      return Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]) <= 1e-6 * scale
        && Math.abs(camera.getViewAngle() - server.view_angle) <= 1e-6 * server.view_angle;
    }
    // pixels from a point to the segment from a to b
    function toSegment(x, y, a, b) {
      const ux = b[0] - a[0], uy = b[1] - a[1], uu = ux * ux + uy * uy;
      const t = uu > 0 ? Math.min(1, Math.max(0, ((x - a[0]) * ux + (y - a[1]) * uy) / uu)) : 0;
      return Math.hypot(x - a[0] - t * ux, y - a[1] - t * uy);
    }
    // pixels between the segments a0-a1 and b0-b1 (0 where they cross)
    function betweenSegments(a0, a1, b0, b1) {
      const side = (p, q, r) => (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
      if (side(a0, a1, b0) * side(a0, a1, b1) < 0 && side(b0, b1, a0) * side(b0, b1, a1) < 0) return 0;
      return Math.min(toSegment(a0[0], a0[1], b0, b1), toSegment(a1[0], a1[1], b0, b1),
                      toSegment(b0[0], b0[1], a0, a1), toSegment(b1[0], b1[1], a0, a1));
    }
    // the place of a letter whose tip is `tip` and arrow runs along (dx, dy): the first free place about
    // its tip, nearest first (covering no letter, nearer no other tip, on no other arrow); else the one
    // that covers, strays and crosses least. `wide`: pixels a shared label's half width exceeds a
    // letter's (0 for a letter alone); it goes that much further along a sideways turn.
    // Twin of render/annotate.place_labels (figures).
    function placeLetter(tip, dx, dy, otherTips, placed, otherShafts = [], wide = 0) {
      let best = null;
      for (let ring = 0; ring < LETTER_RINGS; ring++) {
        for (const turn of LETTER_TURNS) {
          const a = (turn * Math.PI) / 180, c = Math.cos(a), s = Math.sin(a);
          const ux = c * dx - s * dy, uy = s * dx + c * dy;
          const r = LETTER_GAP + ring * LETTER_STEP + wide * Math.abs(ux);
          const x = tip[0] + r * ux, y = tip[1] + r * uy;
          const covers = placed.filter((o) => Math.abs(o.x - x) < LETTER_BOX + wide + o.wide
                                              && Math.abs(o.y - y) < LETTER_BOX).length;
          const strays = otherTips.filter((o) => Math.hypot(o[0] - x, o[1] - y) <= r + 1).length;
          const crosses = otherShafts.filter(([a0, b0]) => (wide > 0
            ? betweenSegments([x - wide, y], [x + wide, y], a0, b0) : toSegment(x, y, a0, b0)) < LETTER_BOX / 2).length;
          if (!covers && !strays && !crosses) return { x, y, wide };
          const cost = 3 * covers + 2 * strays + crosses + ring;
          if (!best || cost < best.cost) best = { x, y, wide, cost };
        }
      }
      return best;
    }
    app.component("phonglab-letters", {
      props: { tips: { type: Array, default: () => [] }, hidden: { type: Boolean, default: false },
               camera: { type: Object, default: null }, covered: { type: Boolean, default: false } },
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
        covered() { this.seen = ""; },
      },
      methods: {
        tick() {
          this.loop = requestAnimationFrame(() => this.tick());
          const view = this.view;
          const renderer = view && view.renderer;
          const canvas = this.host.querySelector("canvas");
          if (!renderer || !canvas || view.phonglabHeld) return; // a held camera: the letters wait with the mesh
          if (view.phonglabLettersHidden) { // a drag over the core's picture: back with its next picture
            this.layer.style.display = "none";
            this.seen = "";
            return;
          }
          const camera = renderer.getActiveCamera();
          // over the core's picture, the letters belong to the picture's camera: none while the view's is
          // another (the camera the server pushed arrives before the picture made for it)
          if (this.covered && this.camera && !sameCamera(camera, this.camera)) {
            this.layer.style.display = "none";
            this.seen = "";
            return;
          }
          // the view angle spans the view's shorter side, as in the server's images (SceneView), so a
          // view taller than wide frames the scene as the per-pixel image does and the letters meet its arrows
          const horizontal = canvas.clientWidth < canvas.clientHeight;
          if (camera.getUseHorizontalViewAngle() !== horizontal) {
            camera.setUseHorizontalViewAngle(horizontal);
            if (view.renderWindow) view.renderWindow.render();
          }
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
          // a letter whose arrow tip the mesh hides (the server casts a ray to it) is not drawn
          const shown = (this.tips || []).filter((x) => !x.behind)
            .map((t, i) => ({ t, i, base: screen(t.base), tip: screen(t.tip) }));
          // arrows whose tips (nearly) meet share one label: tips nearer than LETTER_TOGETHER, chained
          let labels = [];
          for (const s of shown) {
            const near = labels.filter((g) => g.some((o) => Math.hypot(o.tip[0] - s.tip[0], o.tip[1] - s.tip[1]) < LETTER_TOGETHER));
            labels = labels.filter((g) => !near.includes(g)).concat([near.flat().concat([s]).sort((a, b) => a.i - b.i)]);
          }
          labels.sort((a, b) => a[0].i - b[0].i);
          // the spans: each label's letters, with a join between two (a letter in its arrow's colour)
          const pieces = [];
          labels.forEach((g, label) => g.forEach((s, k) => {
            if (k) pieces.push({ label, s: null });
            pieces.push({ label, s });
          }));
          while (layer.children.length > pieces.length) layer.lastChild.remove();
          pieces.forEach((piece, n) => {
            let span = layer.children[n];
            if (!span) { span = document.createElement("span"); layer.appendChild(span); }
            span.className = piece.s ? "phonglab-letter" : "phonglab-letter-join";
            span.textContent = piece.s ? piece.s.t.letter : LETTER_JOIN;
            if (piece.s) span.dataset.letter = piece.s.t.letter; else delete span.dataset.letter;
            span.dataset.label = String(piece.label);
            span.style.color = piece.s ? piece.s.t.color : "";
            piece.span = span;
          });
          const placed = [];
          labels.forEach((g, label) => {
            const mine = pieces.filter((p) => p.label === label);
            // a shared label's width as the page draws it (a letter alone is placed as before)
            const width = g.length > 1 ? mine.reduce((w, p) => w + p.span.offsetWidth, 0) : 0;
            const tip = [0, 1].map((k) => g.reduce((sum, o) => sum + o.tip[k], 0) / g.length);
            const base = [0, 1].map((k) => g.reduce((sum, o) => sum + o.base[k], 0) / g.length);
            let dx = tip[0] - base[0], dy = tip[1] - base[1];
            const length = Math.hypot(dx, dy);
            if (length < 4) { dx = 0; dy = -1; } else { dx /= length; dy /= length; }
            const apart = shown.filter((o) => !g.includes(o) && Math.hypot(o.tip[0] - tip[0], o.tip[1] - tip[1]) >= SAME_TIP);
            const at = placeLetter(tip, dx, dy, apart.map((o) => o.tip), placed, apart.map((o) => [o.base, o.tip]),
                                   Math.max(0, width / 2 - LETTER_BOX / 2));
            placed.push(at);
            // the pieces side by side, centred on the label's place (each span is centred on its left, top)
            let left = at.x - width / 2;
            for (const p of mine) {
              const w = g.length > 1 ? p.span.offsetWidth : 0;
              p.span.style.left = `${(left + w / 2).toFixed(1)}px`;
              p.span.style.top = `${at.y.toFixed(1)}px`;
              left += w;
            }
          });
        },
      },
      template: "<div style='display:none'></div>",
    });
    // <phonglab-address :query="url_query"> writes the server's query of the view (the
    // lesson and the settings that differ from it) into the address bar with
    // history.replaceState, ADDRESS_DELAY ms after the last change (no history entry, no
    // flood while a slider moves; at once when the page is left), and, once, sends the
    // query the page was opened with to the server (url_request, empty when it has none),
    // which checks it, opens that lesson, applies its settings and then shows the page.
    const ADDRESS_DELAY = 250;
    app.component("phonglab-address", {
      props: { query: { type: String, default: "" } },
      mounted() {
        this.pending = null;
        this.timer = null;
        this.write = () => {
          clearTimeout(this.timer);
          this.timer = null;
          const value = this.pending;
          this.pending = null;
          if (value && value !== window.location.search) {
            window.history.replaceState(window.history.state, "", window.location.pathname + value + window.location.hash);
          }
        };
        window.addEventListener("pagehide", this.write);
        // always sent, an empty query too: the server shows the page once the lesson asked for is open
        const asked = window.location.search;
        if (window.trame && window.trame.state) window.trame.state.set("url_request", asked || "");
        if (!asked && this.query) window.history.replaceState(window.history.state, "", window.location.pathname + this.query);
      },
      unmounted() {
        window.removeEventListener("pagehide", this.write);
        clearTimeout(this.timer);
      },
      watch: {
        query(value) {
          this.pending = value;
          clearTimeout(this.timer);
          this.timer = setTimeout(this.write, ADDRESS_DELAY);
        },
      },
      template: "<div style='display:none'></div>",
    });
    // <phonglab-notice-timer :notice="notice">: a notice that only informs ("Applied: …", kind info or
    // success) goes by itself NOTICE_MS after it came, unless another has come since; warnings and errors
    // stay until closed.
    const NOTICE_MS = 4000;
    app.component("phonglab-notice-timer", {
      props: { notice: { type: Object, default: null } },
      watch: {
        notice(value) {
          clearTimeout(this.timer);
          if (!value || !["info", "success"].includes(value.kind)) return;
          const serial = value.serial;
          this.timer = setTimeout(() => {
            const state = window.trame && window.trame.state;
            const shown = state && state.get("notice");
            if (shown && shown.serial === serial) state.set("notice", null);
          }, NOTICE_MS);
        },
      },
      unmounted() {
        clearTimeout(this.timer);
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

// Screen readers hear what the screen shows. A slider's thumb (Vuetify's [role=slider]) says its value
// as aria-valuenow, which is the widget's own number (log10 α for the shininess: 1.48 where the page
// shows 30); its aria-valuetext is set to the value the control shows beside it, whenever that changes.
// The 3D view's focusable box (vtk.js's, around the canvas) gets a name saying what it is and does.
const VIEW_NAME = "The scene in 3D: drag to turn it, the wheel zooms, a click moves the probe";
(function () {
  function speak() {
    for (const control of document.querySelectorAll(".phonglab-control")) {
      const thumb = control.querySelector("[role=slider]");
      const shown = control.querySelector(".phonglab-value");
      const text = shown ? shown.textContent.trim() : "";
      if (thumb && text && thumb.getAttribute("aria-valuetext") !== text) thumb.setAttribute("aria-valuetext", text);
    }
    const canvas = document.querySelector(".phonglab-view canvas");
    const box = canvas && canvas.parentNode;
    if (box && box.hasAttribute("tabindex") && box.getAttribute("aria-label") !== VIEW_NAME) {
      box.setAttribute("role", "application");
      box.setAttribute("aria-label", VIEW_NAME);
    }
  }
  // the letters over the view change every frame of a drag: nothing for a screen reader there
  const elsewhere = (record) => !(record.target.closest && record.target.closest(".phonglab-letters"))
    && !(record.target.parentElement && record.target.parentElement.closest(".phonglab-letters"));
  new MutationObserver((records) => { if (records.some(elsewhere)) speak(); })
    .observe(document.documentElement, { childList: true, subtree: true, characterData: true });
})();

// The check question's feedback comes from the server under the Check button, often below the
// column's fold at laptop sizes: once it shows (or changes) after a press of Check, the column
// scrolls just enough to show it. The check's block is watched only from the press until then (at
// most 30 s), not the whole page all the time: the letters over the view change every frame of a drag.
(function () {
  let watching = null;
  const stop = () => { if (watching) { watching.observer.disconnect(); clearTimeout(watching.timer); watching = null; } };
  document.addEventListener("click", (event) => {
    const button = event.target && event.target.closest && event.target.closest(".phonglab-check-btn");
    const block = button && button.closest(".phonglab-check");
    if (!block) return;
    stop();
    const observer = new MutationObserver(() => {
      const feedback = block.querySelector(".phonglab-check-feedback");
      if (!feedback) return;
      stop();
      feedback.scrollIntoView({ block: "nearest", behavior: "smooth" });
    });
    observer.observe(block, { childList: true, subtree: true, characterData: true });
    watching = { observer, timer: setTimeout(stop, 30000) };
  }, true);
})();

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

// In one column (a narrow window: the view first, the lesson's text last), an experiment applied
// from the text would change a view scrolled far out of sight: the page scrolls the view (and the
// notice over its foot) into sight, so the student sees what the experiment did.
(function () {
  const oneColumn = window.matchMedia("(max-width: 900px)");
  document.addEventListener("click", (event) => {
    if (!oneColumn.matches || !(event.target.closest && event.target.closest(".phonglab-apply"))) return;
    const view = document.querySelector(".phonglab-view");
    const box = view && view.getBoundingClientRect();
    if (!box || (box.bottom >= 80 && box.top <= window.innerHeight - 80)) return;
    // the view's own bar (legend, terms, probe or light) comes first, just below the page's fixed bar
    const target = document.querySelector(".phonglab-viewbar") || view;
    const bar = document.querySelector(".phonglab-bar");
    target.style.scrollMarginTop = `${Math.ceil(bar ? bar.getBoundingClientRect().bottom : 0) + 4}px`;
    target.scrollIntoView({ block: "start" });
  });
})();
