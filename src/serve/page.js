// glint serve's page: the picture (pushed over server-sent events), what is
// under the pointer (from the frame's id buffer, no request), a pixel's
// explain tree and rays on click, the AOVs, the comparison slider.
'use strict';
(function () {
  const token = document.body.dataset.token;
  const $ = (id) => document.getElementById(id);
  const api = (path) => path + (path.includes('?') ? '&' : '?') + 'token=' + encodeURIComponent(token);
  // What the page shows, for people with the console open and for the tests.
  const g = (window.glint = {
    state: null, frame: null, ids: null, pixels: null, shown: {}, last: null,
    raysDrawn: 0, explained: null, view: 'picture', errors: [],
  });
  window.addEventListener('error', (e) => g.errors.push(String(e.message)));
  window.addEventListener('unhandledrejection', (e) => g.errors.push(String(e.reason)));

  const picture = $('picture');
  const overlay = $('overlay');
  const stage = $('stage');

  function el(tag, text, cls) {
    const e = document.createElement(tag);
    if (text !== undefined && text !== null) e.textContent = String(text);
    if (cls) e.className = cls;
    return e;
  }

  // --- state --------------------------------------------------------------
  function onState(s) {
    g.state = s;
    $('file').textContent = s.file;
    const pct = Math.round(100 * (s.progress ? s.progress.fraction : 0));
    $('status').textContent = 'version ' + s.version + ': ' + s.stage + (s.rendering ? ' ' + pct + ' %' : '');
    $('progress').value = s.rendering ? (s.progress ? s.progress.fraction : 0) : 1;
    document.body.dataset.stage = s.stage;
    showDiagnostics(s.diagnostics || []);
    showViews(s);
    showCompare(s);
  }

  function onProgress(p) {
    if (p.total > 0) $('progress').value = p.done / p.total;
  }

  function showDiagnostics(list) {
    const ul = $('diagnostics');
    ul.replaceChildren();
    const errors = list.filter((d) => d.severity === 'error');
    $('diagnostics-box').hidden = list.length === 0;
    $('diagnostics-box').querySelector('h2').textContent = errors.length
      ? 'The scene has errors: the last good picture stays'
      : 'Warnings';
    for (const d of list) {
      const li = el('li');
      li.append(el('span', d.place, 'place'), ' ', el('span', d.severity, d.severity), ': ' + d.message);
      li.append(el('pre', d.text));
      ul.append(li);
    }
  }

  function showViews(s) {
    const nav = $('views');
    const names = ['picture'].concat(s.aovs || []);
    if (s.compare && !s.compare.error) names.push('heat');
    const have = Array.from(nav.children).map((b) => b.dataset.view).join(',');
    if (have !== names.join(',')) {
      nav.replaceChildren();
      for (const n of names) {
        const b = el('button', n);
        b.dataset.view = n;
        b.addEventListener('click', () => setView(n));
        nav.append(b);
      }
    }
    if (!names.includes(g.view)) g.view = 'picture';
    for (const b of nav.children) b.classList.toggle('on', b.dataset.view === g.view);
  }

  function setView(name) {
    g.view = name;
    const img = $('aov');
    if (name === 'picture') {
      img.hidden = true;
    } else {
      const path = name === 'heat' ? '/api/heat.png' : '/api/aov/' + name.replace(':', '-') + '.png';
      img.src = api(path + '?v=' + (g.state ? g.state.good_version : 0));
      img.hidden = false;
    }
    for (const b of $('views').children) b.classList.toggle('on', b.dataset.view === name);
  }

  function showCompare(s) {
    $('compare-bar').hidden = !s.theirs;
    $('compare-box').hidden = !s.theirs;
    $('theirs-clip').hidden = !s.theirs;
    if (!s.theirs) return;
    const img = $('theirs');
    if (!img.getAttribute('src')) img.src = api('/api/theirs.png');
    const c = s.compare;
    let text = 'comparing…';
    if (c && c.error) text = c.error;
    else if (c) {
      const lines = [c.differing + ' of ' + c.size[0] * c.size[1] + ' pixels differ by more than ' + c.threshold + '/255'];
      for (const grp of c.groups.slice(0, 8)) {
        const what = grp.primitive !== null ? grp.type + ' #' + grp.primitive : grp.type;
        lines.push(what + (grp.line ? '  ' + (grp.file || '') + ':' + grp.line : '') + '  ' +
          (100 * grp.share).toFixed(1) + ' % of ' + grp.pixels + ' px differ, ' + grp.black_in_theirs + ' black in yours');
      }
      text = lines.join('\n');
    }
    $('compare-summary').textContent = text;
    clipTheirs();
  }

  function clipTheirs() {
    const v = Number($('compare').value);
    $('theirs-clip').style.clipPath = 'inset(0 0 0 ' + v + '%)';
  }
  $('compare').addEventListener('input', clipTheirs);

  // --- frames -------------------------------------------------------------
  function decodeIds(buf) {
    const v = new DataView(buf);
    if (buf.byteLength < 12 || v.getUint32(0, false) !== 0x474c4944) return null;
    const w = v.getUint32(4, true), h = v.getUint32(8, true);
    const ids = new Int32Array(w * h);
    let at = 0;
    for (let k = 12; k + 8 <= buf.byteLength && at < ids.length; k += 8) {
      const id = v.getInt32(k, true), n = v.getUint32(k + 4, true);
      ids.fill(id, at, Math.min(ids.length, at + n));
      at += n;
    }
    return { w: w, h: h, ids: ids };
  }

  let loading = 0;
  async function onFrame(f) {
    const mine = ++loading;
    const [blob, buf] = await Promise.all([
      fetch(api(f.image)).then((r) => (r.ok ? r.blob() : null)),
      fetch(api(f.ids)).then((r) => (r.ok ? r.arrayBuffer() : null)),
    ]);
    if (mine !== loading || !blob || !buf) return; // a newer frame is on its way
    const img = await createImageBitmap(blob);
    if (mine !== loading) return;
    const ids = decodeIds(buf);
    const [W, H] = f.full;
    if (picture.width !== W || picture.height !== H) {
      picture.width = W; picture.height = H;
      overlay.width = W; overlay.height = H;
    }
    const ctx = picture.getContext('2d');
    ctx.imageSmoothingEnabled = false;
    ctx.drawImage(img, 0, 0, W, H);
    const off = document.createElement('canvas');
    off.width = f.width; off.height = f.height;
    const octx = off.getContext('2d', { willReadFrequently: true });
    octx.drawImage(img, 0, 0);
    g.pixels = octx.getImageData(0, 0, f.width, f.height).data;
    if (g.frame && g.frame.version !== f.version) {
      // What was explained or hovered belongs to the old version.
      $('explain').textContent = 'click a pixel to see its rays and why it is that colour';
      $('hover').textContent = 'move the pointer over the picture';
      g.explained = null;
    }
    g.ids = ids;
    g.frame = f;
    const at = Date.now();
    (g.shown[f.version] = g.shown[f.version] || {})[f.stage] = at;
    g.last = { version: f.version, stage: f.stage, id: f.id, at: at };
    document.body.dataset.frame = f.stage + ' ' + f.version;
    clearRays();
    if (g.view !== 'picture') setView(g.view);
  }

  // --- hover --------------------------------------------------------------
  // The row under the pointer, told at most every 200 ms: the next render
  // (the next save) starts with the bands nearest it.
  let focusSent = 0;
  function focus(y) {
    const now = Date.now();
    if (now - focusSent < 200) return;
    focusSent = now;
    fetch(api('/api/focus?y=' + y)).catch(() => {});
  }

  function pixelAt(e) {
    const f = g.frame;
    if (!f) return null;
    const r = picture.getBoundingClientRect();
    const [W, H] = f.full;
    const x = Math.floor(((e.clientX - r.left) / r.width) * W);
    const y = Math.floor(((e.clientY - r.top) / r.height) * H);
    if (x < 0 || y < 0 || x >= W || y >= H) return null;
    return { x: x, y: y, fx: Math.min(f.width - 1, Math.floor((x * f.width) / W)), fy: Math.min(f.height - 1, Math.floor((y * f.height) / H)) };
  }

  function describe(id) {
    const f = g.frame;
    if (id === -1) return 'background';
    const e = f.legend[String(id)] || {};
    const file = g.state ? g.state.file : '';
    const where = e.line ? '  ' + file + ':' + e.line : '';
    if (id <= -2) return "light #" + (-2 - id) + "'s surface" + where;
    return (e.type || 'primitive') + ' #' + id + where;
  }

  stage.addEventListener('mousemove', (e) => {
    const p = pixelAt(e);
    if (!p || !g.ids) return;
    const k = p.fy * g.ids.w + p.fx;
    const id = g.ids.ids[k];
    const b = g.pixels ? [g.pixels[4 * k], g.pixels[4 * k + 1], g.pixels[4 * k + 2]] : [];
    const coarse = g.frame.stage === 'coarse' ? '  (coarse preview)'
      : g.frame.stage === 'bands' ? '  (rendering: bands at full resolution come in)' : '';
    focus(p.y);
    $('hover').textContent = '(' + p.x + ', ' + p.y + ')  ' + describe(id) + '  bytes ' + b.join(' ') + coarse;
  });

  // --- click: explain -----------------------------------------------------
  function clearRays() {
    overlay.getContext('2d').clearRect(0, 0, overlay.width, overlay.height);
    g.raysDrawn = 0;
  }

  const colours = { camera: '#ffeb3b', reflection: '#4fc3f7', glossy: '#81d4fa', refraction: '#a5d6a7',
    total_internal_reflection: '#ce93d8', shadow: '#ff8a65' };

  function drawRays(rays, x, y) {
    clearRays();
    const ctx = overlay.getContext('2d');
    const scale = Math.max(1, overlay.width / 640);
    ctx.lineWidth = 1.5 * scale;
    for (const r of rays) {
      ctx.strokeStyle = colours[r.kind] || '#fff';
      ctx.setLineDash(r.kind === 'shadow' ? [4 * scale, 3 * scale] : []);
      ctx.globalAlpha = r.kind === 'shadow' && r.hit ? 0.5 : 1;
      ctx.beginPath();
      ctx.moveTo(r.from[0], r.from[1]);
      ctx.lineTo(r.to[0], r.to[1]);
      ctx.stroke();
    }
    ctx.globalAlpha = 1;
    ctx.setLineDash([]);
    ctx.strokeStyle = '#fff';
    ctx.strokeRect(x - 3 * scale, y - 3 * scale, 7 * scale, 7 * scale);
    g.raysDrawn = rays.length;
  }

  function nodeView(n, file) {
    const d = el('details');
    d.open = n.depth <= 2;
    let head = n.kind + (n.k ? ' ' + n.k + '/' + n.n : '') + '  depth ' + n.depth;
    if (n.kind === 'glossy_fan') {
      head = 'glossy fan of ' + n.count + ' rays, depth ' + n.depth + ', mean ' + fmt(n.mean);
      d.append(el('summary', head));
      return d;
    }
    if (n.hit) {
      const h = n.hit;
      const what = h.primitive !== null ? h.type + ' #' + h.primitive : "light #" + h.light + "'s surface";
      head += '  hit ' + what + (h.line ? '  ' + (file || '') + ':' + h.line : '') + '  t ' + num(h.t) + (h.front ? '  front' : '  back');
    } else {
      head += '  missed: background';
    }
    head += '  -> ' + fmt(n.color);
    d.append(el('summary', head));
    for (const l of n.lights || []) {
      let t = 'light #' + l.light + ' ' + l.type + (l.line ? ' (' + (file || '') + ':' + l.line + ')' : '') +
        '  L·N ' + num(l.l_dot_n) + '  shade ' + l.shade + '  diffuse ' + num(l.diffuse) + '  specular ' + num(l.specular);
      if (l.blocker) t += '  blocked by ' + l.blocker.type + (l.blocker.line ? ' ' + (file || '') + ':' + l.blocker.line : '');
      d.append(el('div', t));
    }
    for (const c of n.children || []) d.append(nodeView(c, file));
    return d;
  }
  function num(v) { return v === null || v === undefined ? '-' : Number(v).toFixed(4); }
  function fmt(v) { return v ? '(' + v.map(num).join(', ') + ')' : '-'; }

  stage.addEventListener('click', async (e) => {
    const p = pixelAt(e);
    if (!p) return;
    const box = $('explain');
    box.textContent = 'explaining (' + p.x + ', ' + p.y + ')…';
    const r = await fetch(api('/api/explain?x=' + p.x + '&y=' + p.y));
    if (!r.ok) { box.textContent = await r.text(); return; }
    const j = await r.json();
    g.explained = j;
    const ex = j.explain;
    box.replaceChildren();
    box.append(el('div', 'pixel (' + ex.pixel[0] + ', ' + ex.pixel[1] + ') -> bytes ' + ex.bytes.join(' ') +
      '  (' + ex.samples.length + ' sample' + (ex.samples.length === 1 ? '' : 's') + ')'));
    box.append(el('div', ex.verdict, 'verdict'));
    ex.samples.slice(0, 49).forEach((s) => box.append(nodeView(s, ex.file)));
    const raw = el('details');
    raw.append(el('summary', 'as text (glint explain)'), el('pre', j.text));
    box.append(raw);
    drawRays(j.rays, p.x + 0.5, p.y + 0.5);
  });

  // --- the event stream ---------------------------------------------------
  const events = new EventSource(api('/api/events'));
  const on = (name, f) => events.addEventListener(name, (e) => {
    try { f(JSON.parse(e.data)); } catch (err) { g.errors.push(String(err)); }
  });
  on('state', onState);
  on('progress', onProgress);
  on('frame', (f) => { onFrame(f).catch((err) => g.errors.push(String(err))); });
  events.onerror = () => { $('status').textContent = 'reconnecting…'; };
})();
