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
        apply() {
          const push = this.pending;
          if (!push || !push.data) return;
          const found = this.findArray(push.dataset, push.name, push.location);
          if (!found) {
            // the first scene may still be on its way: try again next frame
            if (this.tries++ < 120) requestAnimationFrame(() => this.apply());
            return;
          }
          const raw = push.data;
          const bytes = raw instanceof ArrayBuffer ? new Uint8Array(raw) : new Uint8Array(raw.buffer, raw.byteOffset, raw.byteLength);
          const old = found.array.getData();
          // a size mismatch means the geometry changed: the full sync brings the colours
          if (bytes.byteLength !== old.byteLength) return;
          // a new typed array (never overwrite: the old one may be cached by hash)
          const values = new old.constructor(old.length);
          new Uint8Array(values.buffer).set(bytes);
          found.array.setData(values, found.array.getNumberOfComponents());
          found.data.modified();
          this.pending = null;
          // draw now rather than on the view's next debounced render
          if (this.view.renderer) this.view.renderer.resetCameraClippingRange();
          this.view.renderWindow.render();
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
