// phonglab's page: fitting formulas to their boxes (loaded with phonglab.js).
//
// Formulas live in narrow columns: the lesson's display formulas (.math-block) and the
// readout's substituted equation (.eq-row). One wider than its box is first scaled down,
// but not below MIN_SCALE of its size (smaller indices become unreadable); if it still
// does not fit, it is broken into lines before its top-level operators (=, ≈, +, −, then
// · and ∘), each continuation line indented: each side of an = on its own line once a row
// is broken at all, and a fraction wider than a line with its denominator in lines; a piece
// that is still too wide scrolls sideways within its box, with a fade at the edge where
// more of it is hidden.
(function () {
  const MIN_SCALE = 0.9;
  // break before these operators, the first group first
  const BREAKS = [["=", "≈", "≤", "≥", "<", ">", "→"], ["+", "−", "-", "±"], ["·", "∘", "×"]];
  const OPEN = "([{⟨|‖", CLOSE = ")]}⟩|‖";
  const originals = new WeakMap();

  // the operator an element of a row starts with (a sub/superscript's base counts)
  function opText(el) {
    const tag = el.localName;
    if (tag === "mo") return el.textContent.trim();
    if (tag === "msup" || tag === "msub" || tag === "msubsup") return el.firstElementChild ? opText(el.firstElementChild) : null;
    return null;
  }

  // a prime written as a superscript (α′ from \alpha') is set after its letter, as a prime glyph
  // (already raised by the font), not shrunk again as a script of a script
  function markPrimes(math) {
    math.querySelectorAll("msup").forEach((sup) => {
      const [base, script] = sup.children;
      if (!base || !script || sup.children.length !== 2 || !/^[′″‴]+$/.test(script.textContent.trim())) return;
      const row = document.createElementNS(sup.namespaceURI, "mrow");
      const prime = document.createElementNS(sup.namespaceURI, "mi");
      prime.textContent = script.textContent.trim();
      prime.setAttribute("class", "math-prime");
      row.append(base, prime);
      sup.replaceWith(row);
    });
  }

  // the box a formula must fit in, and its <math>: the .math-block itself, or a .math-fit around
  // an equation row's formula (added here once)
  function boxOf(el) {
    if (el.classList.contains("math-block")) return el;
    const math = el.querySelector(":scope > math");
    if (!math) return el.querySelector(":scope > .math-fit");
    const box = document.createElement("div");
    box.className = "math-fit";
    math.replaceWith(box);
    box.appendChild(math);
    return box;
  }

  // the formula as the server sent it (kept on first sight; put back before each new fitting)
  function restore(box) {
    let math = box.querySelector(":scope > math");
    if (!math) return null;
    const original = originals.get(box);
    if (!original) originals.set(box, math.cloneNode(true));
    else if (math.querySelector("mtable.math-lines")) {
      const fresh = original.cloneNode(true);
      math.replaceWith(fresh);
      math = fresh;
    }
    return math;
  }

  // the pieces of a formula's row (groups such as [ ... ] opened up) and the indices before which
  // it may break, by priority: outside brackets (=, then + −, then · ∘, then between two bracketed
  // factors, ")(" ), then inside big brackets (\left[ ... \right]); never inside small ones,
  // such as max(0, n·l)
  function breakPoints(row, deep = true) {
    const kids = [];
    const open = (el) => Array.from(el.children).forEach((kid) => (deep && kid.localName === "mrow" ? open(kid) : kids.push(kid)));
    open(row);
    const points = BREAKS.map(() => []).concat([[]], BREAKS.map(() => []));
    const FACTOR = BREAKS.length, INSIDE = BREAKS.length + 1;
    const stack = []; // 1 for a big bracket, 2 for a small one
    const depth = () => stack.reduce((a, b) => a + b, 0);
    kids.forEach((kid, i) => {
      const op = opText(kid);
      const opens = op && op.length === 1 && OPEN.includes(op) && !CLOSE.includes(op);
      const closes = op && op.length === 1 && CLOSE.includes(op) && !OPEN.includes(op);
      const d = depth();
      if (op && i > 0 && d <= 1) {
        const level = BREAKS.findIndex((group) => group.includes(op));
        if (level >= 0) points[d ? INSIDE + level : level].push(i);
        let k = i - 1;
        while (k > 0 && kids[k].localName === "mspace") k--; // a thin space between the factors
        const before = opText(kids[k]);
        if (opens && d === 0 && before && before.length === 1 && CLOSE.includes(before)) points[FACTOR].push(i);
      }
      if (opens) {
        const mo = kid.localName === "mo" ? kid : kid.firstElementChild;
        stack.push(mo && mo.getAttribute("stretchy") === "true" ? 1 : 2);
      } else if (closes) stack.pop();
    });
    return { kids, points };
  }

  // lines of a row that fit in `room`: break before operators of the highest priority that
  // does (greedy, each line as long as fits), else add the next group of operators; returns
  // {parts: lists of children, inner: per line, whether it continues a side (indented twice)},
  // or null when the row cannot be broken
  function lines(row, room) {
    // groups stay whole (their brackets keep their size) when breaking outside them is enough
    const outside = linesOf(row, room, false);
    return outside && outside.fits ? outside : linesOf(row, room, true) || outside || null;
  }

  function linesOf(row, room, deep) {
    const { kids, points } = breakPoints(row, deep);
    if (kids.length < 2) return null;
    const left = kids.map((k) => k.getBoundingClientRect().left);
    const right = kids.map((k) => k.getBoundingClientRect().right);
    const indent = 1.2 * parseFloat(getComputedStyle(row).fontSize);
    // a line from a relation is indented once; a line within a side (after a relation's line), twice
    let sides = false;
    const width = (from, to) => right[to - 1] - left[from] + (!from ? 0 : sides && !points[0].includes(from) ? 2 * indent : indent);
    // cuts within [start, end): each line as long as fits, before one of `allowed`
    const greedy = (start, end, allowed) => {
      const cuts = [];
      let from = start, last = null;
      for (const at of allowed.filter((p) => p > start && p < end).concat([end])) {
        if (width(from, at) <= room) { last = at; continue; }
        if (last !== null && last > from && last < end) { cuts.push(last); from = last; }
        if (at < end && width(from, at) > room && at > from) { cuts.push(at); from = at; last = null; }
        else last = at;
      }
      return cuts;
    };
    const bounds = (cuts) => [[0].concat(cuts), cuts.concat([kids.length])];
    const fitting = (cuts) => { const [starts, ends] = bounds(cuts); return starts.every((s, i) => width(s, ends[i]) <= room); };
    // a chain of relations (a worked row: formula = numbers = value) is cut at its relations first, so
    // that a side broken within never shares a line with another side: "= 0.040 + (1 − 0.040)·…" then
    // reads as the substitution, not as the formula's value; a side still too wide is then broken
    // within at the next operators (+ −, then · ∘, ...). A single relation (the lesson's "I = …")
    // may keep its short left side on the first line.
    const chain = points[0].length > 1;
    const fixed = chain ? greedy(0, kids.length, points[0]) : [];
    sides = fixed.length > 0;
    let cuts = fixed;
    if (!fitting(cuts)) {
      let allowed = [];
      for (const level of chain ? points.slice(1) : points) {
        if (!level.length) continue;
        allowed = allowed.concat(level).sort((a, b) => a - b);
        const [starts, ends] = bounds(fixed);
        cuts = fixed.slice();
        starts.forEach((s, i) => { if (width(s, ends[i]) > room) cuts.push(...greedy(s, ends[i], allowed)); });
        cuts.sort((a, b) => a - b);
        if (fitting(cuts)) break;
      }
    }
    if (!cuts.length) return null;
    const [starts, ends] = bounds(cuts);
    return { parts: starts.map((s, i) => kids.slice(s, ends[i])), fits: fitting(cuts),
             inner: starts.map((s) => s > 0 && sides && !points[0].includes(s)) };
  }

  // a piece that starts with its operator keeps the operator's spacing (binary, not a sign)
  function infix(mrow) {
    const first = mrow.firstElementChild;
    const binary = first && first.localName === "mo" && BREAKS.some((group) => group.includes(first.textContent.trim()));
    if (binary && !first.hasAttribute("form")) first.setAttribute("form", "infix");
    return mrow;
  }

  // a one-column table of a row's lines (the first line's pieces, then each continuation line from its
  // operator on; a line within a side marked to be indented twice)
  function linesTable(ns, found) {
    const table = document.createElementNS(ns, "mtable");
    table.setAttribute("class", "math-lines");
    found.parts.forEach((part, i) => {
      const tr = document.createElementNS(ns, "mtr");
      const td = document.createElementNS(ns, "mtd");
      if (found.inner[i]) td.setAttribute("class", "math-inner");
      const mrow = document.createElementNS(ns, "mrow");
      part.forEach((kid) => mrow.appendChild(kid.cloneNode(true)));
      td.appendChild(i ? infix(mrow) : mrow);
      tr.appendChild(td);
      table.appendChild(tr);
    });
    return table;
  }

  // the formula, still one <math>, as a table of its lines
  function breakInto(box, math, room) {
    let row = math;
    while (row.children.length === 1 && ["mrow", "semantics"].includes(row.firstElementChild.localName)) row = row.firstElementChild;
    const found = lines(row, room);
    if (!found) return false;
    math.replaceChildren(linesTable(math.namespaceURI, found));
    return true;
  }

  // a fraction too wide for a line of its own (a long denominator, such as V's 2(n·l √(…) + n·v √(…)) with
  // its numbers put in) cannot be cut at the row's operators: its denominator is broken into lines
  // (a table under the fraction bar), at its own operators, continuation lines indented
  function breakFractions(math, room) {
    const indent = 1.2 * parseFloat(getComputedStyle(math).fontSize);
    let broken = false;
    math.querySelectorAll("mfrac").forEach((frac) => {
      if (frac.children.length !== 2 || frac.getBoundingClientRect().width <= room - indent) return;
      let row = frac.children[1];
      while (row.children.length === 1 && row.firstElementChild.localName === "mrow") row = row.firstElementChild;
      const found = lines(row, room - 2 * indent);
      if (!found) return;
      frac.children[1].replaceWith(linesTable(math.namespaceURI, found));
      broken = true;
    });
    return broken;
  }

  function fit(el) {
    const box = boxOf(el);
    if (!box) return;
    const math = restore(box);
    if (!math) return;
    markPrimes(math);
    box.style.removeProperty("--math-scale");
    // the room inside the box's padding (a readout row indents its formula with padding)
    const pad = getComputedStyle(box);
    const room = box.clientWidth - (parseFloat(pad.paddingLeft) || 0) - (parseFloat(pad.paddingRight) || 0);
    let natural = math.scrollWidth;
    if (room && natural > room) {
      let scale = 1;
      // MathML does not scale exactly with the font size: correct twice at most
      for (let i = 0; i < 3 && natural > room && scale > MIN_SCALE; i++) {
        scale = Math.max(MIN_SCALE, scale * room / natural);
        box.style.setProperty("--math-scale", scale.toFixed(4));
        natural = math.scrollWidth;
      }
      if (natural > room) {
        // still too wide: full size again, in lines (a fraction wider than a line, its denominator first)
        box.style.removeProperty("--math-scale");
        if (breakFractions(math, room)) natural = math.scrollWidth;
        if (natural > room) breakInto(box, math, room);
      }
    }
    edges(box);
  }

  // a long formula within a line of text is cut into formulas side by side, before its top-level
  // relations and + or −, so that the line may wrap between them (once per formula)
  const INLINE_SPLIT = 160; // px: shorter formulas stay whole
  function splitInline(math) {
    if (math.dataset.split || math.closest(".math-block, .eq-row, .math-pieces")) return;
    math.dataset.split = "1";
    markPrimes(math);
    if (math.getBoundingClientRect().width <= INLINE_SPLIT) return;
    let row = math;
    while (row.children.length === 1 && ["mrow", "semantics"].includes(row.firstElementChild.localName)) row = row.firstElementChild;
    const { kids, points } = breakPoints(row, false);
    const cuts = points[0].concat(points[1]).sort((a, b) => a - b);
    if (!cuts.length) return;
    const holder = document.createElement("span");
    holder.className = "math-pieces";
    const starts = [0].concat(cuts), ends = cuts.concat([kids.length]);
    starts.forEach((from, i) => {
      if (i) holder.appendChild(document.createElement("wbr"));
      const copy = math.cloneNode(false);
      copy.dataset.split = "1";
      const mrow = document.createElementNS(math.namespaceURI, "mrow");
      kids.slice(from, ends[i]).forEach((kid) => mrow.appendChild(kid.cloneNode(true)));
      copy.appendChild(i ? infix(mrow) : mrow);
      holder.appendChild(copy);
    });
    math.replaceWith(holder);
  }

  // fades on the sides where part of the formula is scrolled out of sight
  function edges(block) {
    const hidden = block.scrollWidth - block.clientWidth;
    block.classList.toggle("math-more-right", hidden > 1 && block.scrollLeft < hidden - 1);
    block.classList.toggle("math-more-left", hidden > 1 && block.scrollLeft > 1);
  }

  let pending = false;
  let observer = null;
  function fitAll() {
    if (pending) return;
    pending = true;
    requestAnimationFrame(() => {
      pending = false;
      document.querySelectorAll(".math-block, .eq-row").forEach(fit);
      document.querySelectorAll(".phonglab-text math:not([display=block])").forEach(splitInline);
      if (observer) observer.takeRecords(); // our own lines are not news
    });
  }

  const holdsFormula = (node) =>
    node.nodeType === 1 && (node.matches(".math-block, .eq-row, math") || node.querySelector(".math-block, .eq-row, math"));
  observer = new MutationObserver((records) => {
    if (records.some((r) => Array.from(r.addedNodes).some(holdsFormula))) fitAll();
  });
  observer.observe(document.documentElement, { childList: true, subtree: true });
  // the columns change width with the window (and the grid)
  new ResizeObserver(fitAll).observe(document.documentElement);
  window.addEventListener("resize", fitAll);
  document.addEventListener("scroll", (event) => {
    const t = event.target;
    if (t.classList && (t.classList.contains("math-block") || t.classList.contains("math-fit"))) edges(t);
  }, true);
  window.phonglabFitMath = fitAll;
})();
