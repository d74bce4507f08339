#!/usr/bin/env node
// Renders every HTML page of the crate's rustdoc in headless Chromium with KaTeX, as a docs.rs
// reader sees it, and reports formulas that a reader would see broken. Called by .ci/check-math,
// which builds the docs and fetches what this needs; no npm dependencies (Chromium is driven
// through the DevTools protocol over a pipe).
//
// usage: node check-math.js --doc DIR (--katex DIST | --offline) --src DIR [PAGE...] [--shots DIR PAGE...]
//   --doc    the crate's rustdoc folder (target/doc/jeffcott)
//   --katex  a local KaTeX dist/ folder: requests for `.../katex@VERSION/dist/FILE` (the header's
//            CDN) are answered from it, so the pages are checked exactly as generated
//   --src    the crate's src/: each rendered formula is traced back to the doc comment that
//            wrote it, and that source is checked for what rustdoc's Markdown eats
//   --offline  no network at all: KaTeX must load from the pages' own folder (docs/doc.sh's
//            copy, docs/katex/header.html) with its fonts; a request for KaTeX's CDN is an error
//   PAGE     check only these pages (paths relative to --doc; default: every page)
//   --shots  write full-page PNG screenshots of the listed pages
// Exit status: 0 when every page is clean, 1 when any error is found, 2 when the check itself fails.
'use strict';
const fs = require('fs');
const path = require('path');
const { spawn } = require('child_process');

// ---------------------------------------------------------------------------------------------
// Arguments
const args = { shots: null, pages: [] };
{
  const argv = process.argv.slice(2);
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    if (a === '--doc') args.doc = path.resolve(argv[++i]);
    else if (a === '--katex') args.katex = path.resolve(argv[++i]);
    else if (a === '--src') args.src = path.resolve(argv[++i]);
    else if (a === '--shots') args.shots = path.resolve(argv[++i]);
    else if (a === '--offline') args.offline = true;
    else if (a === '--chromium') args.chromium = argv[++i];
    else args.pages.push(a);
  }
  args.chromium = args.chromium || process.env.CHROMIUM || '/usr/bin/chromium';
  for (const k of args.offline ? ['doc', 'src'] : ['doc', 'katex', 'src']) {
    if (!args[k]) die(`missing --${k}`);
  }
}

function die(msg) {
  console.error(`check-math: ${msg}`);
  process.exit(2);
}

// ---------------------------------------------------------------------------------------------
// Source side: the math written in doc comments, and what Markdown does to it.

// ASCII punctuation: what CommonMark lets a backslash escape.
const PUNCT = /[!-\/:-@\[-`{-~]/;

function walk(dir, ext, out = []) {
  for (const e of fs.readdirSync(dir, { withFileTypes: true })) {
    const p = path.join(dir, e.name);
    if (e.isDirectory()) walk(p, ext, out);
    else if (e.name.endsWith(ext)) out.push(p);
  }
  return out.sort();
}

// Doc comment blocks of a Rust file: consecutive `///` or `//!` lines, as (text, line of each char).
function docBlocks(file) {
  const lines = fs.readFileSync(file, 'utf8').split('\n');
  const blocks = [];
  let cur = null;
  lines.forEach((l, i) => {
    const m = /^\s*\/\/([\/!])(?!\/)( ?)(.*)$/.exec(l);
    if (m && !(m[1] === '/' && /^\s*\/\/\/\//.test(l))) {
      if (!cur || cur.kind !== m[1]) {
        cur = { kind: m[1], text: '', lineOf: [] };
        blocks.push(cur);
      }
      const t = m[3] + '\n';
      cur.text += t;
      for (let k = 0; k < t.length; k++) cur.lineOf.push(i + 1);
    } else {
      cur = null;
    }
  });
  return blocks;
}

// Blank out fenced code blocks and inline code spans (rustdoc renders them as code: KaTeX skips them).
function maskCode(text) {
  const out = text.split('');
  const lines = text.split('\n');
  let pos = 0;
  let fence = null;
  for (const l of lines) {
    const f = /^\s*(```+|~~~+)/.exec(l);
    const blank = () => { for (let k = pos; k < pos + l.length; k++) out[k] = ' '; };
    if (fence) {
      blank();
      if (f && f[1][0] === fence[0] && f[1].length >= fence.length) fence = null;
    } else if (f) {
      fence = f[1];
      blank();
    }
    pos += l.length + 1;
  }
  const s = out.join('');
  // Inline code: a run of N backticks up to the next run of exactly N.
  return s.replace(/(`+)([\s\S]*?[^`])\1(?!`)/g, (m) => ' '.repeat(m.length));
}

// Math spans as KaTeX's auto-render finds them ($$...$$ display, then $...$ inline), on the source
// text: a backslash skips the next character and the closing delimiter must be at brace depth 0.
function mathSpans(text) {
  const spans = [];
  let i = 0;
  while (i < text.length) {
    if (text[i] === '\\') { i += 2; continue; }
    if (text[i] !== '$') { i++; continue; }
    const display = text[i + 1] === '$';
    const open = display ? 2 : 1;
    let j = i + open;
    let depth = 0;
    let end = -1;
    while (j < text.length) {
      const c = text[j];
      if (c === '\\') { j += 2; continue; }
      if (c === '{') depth++;
      else if (c === '}') depth--;
      else if (depth <= 0 && c === '$' && (!display || text[j + 1] === '$')) { end = j; break; }
      if (!display && c === '\n' && text[j + 1] === '\n') break; // a paragraph ends inline math
      j++;
    }
    if (end < 0) { i += open; continue; }
    spans.push({ start: i, tex: text.slice(i + open, end), display });
    i = end + open;
  }
  return spans;
}

// What rustdoc's Markdown hands on: backslash escapes of ASCII punctuation are removed.
const mdUnescape = (s) => s.replace(/\\([!-\/:-@\[-`{-~])/g, '$1');
// Smart punctuation, undone, so that the rendered text can be matched to its source.
const unSmart = (s) => s.replace(/[\u2018\u2019]/g, "'").replace(/[\u201c\u201d]/g, '"')
  .replace(/\u2014/g, '---').replace(/\u2013/g, '--').replace(/\u2026/g, '...');
const norm = (s) => s.replace(/\s+/g, ' ').trim();

// Named TeX spellings that Markdown leaves alone, for the fix hints.
const SURVIVES = {
  ',': '\\thinspace', ';': '\\thickspace', ':': '\\medspace', '!': '\\negthinspace',
  '{': '\\lbrace', '}': '\\rbrace', '|': '\\Vert', '_': '\\_ (write \\\\_)', '&': '\\& (write \\\\&)',
  '%': '\\% (write \\\\%)', '#': '\\# (write \\\\#)', '$': '\\$ (write \\\\$)',
};

// What Markdown does to one formula as written: a list of problems, each with a fix.
function lintSource(tex) {
  const issues = [];
  const re = /(\\+)([\s\S]?)/g;
  let m;
  while ((m = re.exec(tex))) {
    const n = m[1].length;
    const c = m[2];
    if (n % 2 === 1 && c && PUNCT.test(c) && !(n === 1 && (c === '_' || c === '*'))) {
      const fix = SURVIVES[c] ? `write ${SURVIVES[c]}` : `write \\\\${c}`;
      issues.push(`\`${m[1]}${c}\`: Markdown eats the backslash, KaTeX gets \`${'\\'.repeat((n - 1) / 2)}${c}\` (${fix})`);
    } else if (n % 4 === 2 && (c === '' || /\s/.test(c))) {
      issues.push('`\\\\` before a space or line end: Markdown makes it `\\` (a control space), the row break is lost (write `\\\\\\\\`)');
    }
    if (!c) break;
  }
  const starts = /\n[ \t]*([-+*>#]|\d+[.)])(?=[ \t])/.exec(tex);
  if (starts) issues.push(`a line of the formula starts with \`${starts[1]}\`: Markdown reads a list item, quote or heading there and splits the formula (move it to the line before)`);
  if (/'/.test(tex)) issues.push("`'`: smart punctuation makes it a curly quote (write `^\\prime`, `^{\\prime\\prime}`)");
  if (/"/.test(tex)) issues.push('`"`: smart punctuation makes it a curly quote');
  if (/\.\.\./.test(tex)) issues.push('`...`: smart punctuation makes it `\u2026` (write `\\ldots` or `\\dots`)');
  if (/--/.test(tex)) issues.push('`--`: smart punctuation makes it a dash');
  return issues;
}

// Every formula written in src/, keyed by what KaTeX receives once Markdown has been through it.
const sources = new Map();
const allSources = [];
for (const file of walk(args.src, '.rs')) {
  const rel = path.relative(path.dirname(args.src), file);
  for (const b of docBlocks(file)) {
    for (const s of mathSpans(maskCode(b.text))) {
      const entry = { where: `${rel}:${b.lineOf[s.start]}`, tex: s.tex, display: s.display, issues: lintSource(s.tex), seen: false };
      allSources.push(entry);
      const key = norm(mdUnescape(s.tex));
      if (!sources.has(key)) sources.set(key, []);
      sources.get(key).push(entry);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Chromium over the DevTools protocol (--remote-debugging-pipe: fd 3 in, fd 4 out, NUL-separated).
class Browser {
  constructor(exe, userDir) {
    this.proc = spawn(exe, [
      '--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync',
      '--disable-extensions', '--hide-scrollbars', '--mute-audio', '--remote-debugging-pipe',
      `--user-data-dir=${userDir}`, 'about:blank',
    ], { stdio: ['ignore', 'ignore', 'pipe', 'pipe', 'pipe'] });
    this.stderr = '';
    this.proc.stderr.on('data', (d) => { this.stderr = (this.stderr + d).slice(-4000); });
    this.proc.on('exit', (code) => {
      if (!this.closing) die(`chromium exited (${code}):\n${this.stderr}`);
    });
    this.id = 0;
    this.pending = new Map();
    this.handlers = [];
    let buf = '';
    this.proc.stdio[4].on('data', (d) => {
      buf += d.toString('utf8');
      let k;
      while ((k = buf.indexOf('\0')) >= 0) {
        const msg = JSON.parse(buf.slice(0, k));
        buf = buf.slice(k + 1);
        if (msg.id && this.pending.has(msg.id)) {
          const { resolve, reject } = this.pending.get(msg.id);
          this.pending.delete(msg.id);
          if (msg.error) reject(new Error(`${msg.error.message} ${msg.error.data || ''}`));
          else resolve(msg.result);
        } else if (msg.method) {
          for (const h of this.handlers) h(msg);
        }
      }
    });
  }
  send(method, params = {}, sessionId) {
    const id = ++this.id;
    const msg = { id, method, params };
    if (sessionId) msg.sessionId = sessionId;
    this.proc.stdio[3].write(JSON.stringify(msg) + '\0');
    return new Promise((resolve, reject) => this.pending.set(id, { resolve, reject }));
  }
  on(h) { this.handlers.push(h); }
  async close() {
    this.closing = true;
    const exited = new Promise((resolve) => {
      if (this.proc.exitCode !== null) resolve();
      else this.proc.on('exit', resolve);
    });
    this.send('Browser.close').catch(() => {});
    const timer = setTimeout(() => this.proc.kill('SIGKILL'), 5000);
    await exited;
    clearTimeout(timer);
  }
}

const MIME = { '.js': 'application/javascript', '.css': 'text/css', '.woff2': 'font/woff2',
  '.woff': 'font/woff', '.ttf': 'font/ttf' };

// One tab: KaTeX's CDN answered from the local copy, every other network request refused.
async function openTab(browser, stats) {
  const { targetId } = await browser.send('Target.createTarget', { url: 'about:blank' });
  const { sessionId } = await browser.send('Target.attachToTarget', { targetId, flatten: true });
  const tab = { sessionId, console: [], loaded: null, blocked: [] };
  const send = (m, p) => browser.send(m, p, sessionId);
  tab.send = send;
  browser.on(async (msg) => {
    if (msg.sessionId !== sessionId) return;
    if (msg.method === 'Page.loadEventFired' && tab.loaded) tab.loaded();
    else if (msg.method === 'Runtime.consoleAPICalled') {
      const text = msg.params.args.map((a) => a.value !== undefined ? String(a.value) : (a.description || '')).join(' ');
      tab.console.push({ type: msg.params.type, text });
    } else if (msg.method === 'Runtime.exceptionThrown') {
      const d = msg.params.exceptionDetails;
      tab.console.push({ type: 'exception', text: (d.exception && d.exception.description) || d.text });
    } else if (msg.method === 'Fetch.requestPaused') {
      const { requestId, request } = msg.params;
      const m = /\/katex@[^/]+\/dist\/([^?#]+)/.exec(request.url);
      const file = m && !args.offline && path.join(args.katex, m[1]);
      try {
        if (file && file.startsWith(args.katex) && fs.existsSync(file)) {
          stats.katexServed++;
          await send('Fetch.fulfillRequest', {
            requestId, responseCode: 200,
            responseHeaders: [
              { name: 'Content-Type', value: MIME[path.extname(file)] || 'application/octet-stream' },
              { name: 'Access-Control-Allow-Origin', value: '*' },
            ],
            body: fs.readFileSync(file).toString('base64'),
          });
        } else {
          tab.blocked.push(request.url);
          await send('Fetch.failRequest', { requestId, errorReason: 'BlockedByClient' });
        }
      } catch (e) { /* the page went away meanwhile */ }
    }
  });
  await send('Page.enable');
  await send('Runtime.enable');
  await send('Fetch.enable', { patterns: [{ urlPattern: 'http://*' }, { urlPattern: 'https://*' }] });
  await send('Emulation.setDeviceMetricsOverride', { width: 1280, height: 900, deviceScaleFactor: 1, mobile: false });
  return tab;
}

async function load(tab, url, timeoutMs = 30000) {
  tab.console = [];
  tab.blocked = [];
  const loaded = new Promise((resolve, reject) => {
    tab.loaded = resolve;
    setTimeout(() => reject(new Error(`timeout loading ${url}`)), timeoutMs);
  });
  await tab.send('Page.navigate', { url });
  await loaded;
  tab.loaded = null;
}

// Runs in the page once KaTeX's auto-render has run (it renders on DOMContentLoaded).
function inspectPage() {
  const skip = new Set(['SCRIPT', 'NOSCRIPT', 'STYLE', 'TEXTAREA', 'PRE', 'CODE']);
  const out = { katex: typeof window.katex === 'object', formulas: [], errors: [], stray: [], texOutside: [] };
  for (const el of document.querySelectorAll('.katex')) {
    if (el.closest('.katex-display') && !el.parentElement.classList.contains('katex-display')) continue;
    const ann = el.querySelector('annotation[encoding="application/x-tex"]');
    const tex = ann ? ann.textContent : '';
    let strict = null;
    try {
      window.katex.renderToString(tex, { displayMode: !!el.closest('.katex-display'), strict: 'error', throwOnError: true });
    } catch (e) { strict = String(e.message || e); }
    out.formulas.push({ tex, display: !!el.closest('.katex-display'), strict });
  }
  for (const el of document.querySelectorAll('.katex-error')) {
    out.errors.push({ tex: el.textContent, message: el.getAttribute('title') || '' });
  }
  // Text a reader sees outside math and code: a `$` or a TeX command there is math left unrendered.
  const block = (n) => {
    let e = n.parentElement;
    while (e && getComputedStyle(e).display === 'inline') e = e.parentElement;
    return e || n.parentElement;
  };
  const seen = new Set();
  const tw = document.createTreeWalker(document.body, NodeFilter.SHOW_TEXT, {
    acceptNode(n) {
      for (let e = n.parentElement; e; e = e.parentElement) {
        if (skip.has(e.tagName) || e.classList.contains('katex') || e.classList.contains('katex-display')) return NodeFilter.FILTER_REJECT;
      }
      return NodeFilter.FILTER_ACCEPT;
    },
  });
  for (let n = tw.nextNode(); n; n = tw.nextNode()) {
    const t = n.textContent;
    const dollar = t.includes('$') || /\\[()[\]]/.test(t);
    const cmd = /\\[A-Za-z]+/.exec(t);
    if (!dollar && !cmd) continue;
    const b = block(n);
    if (seen.has(b)) continue;
    seen.add(b);
    // The passage as a reader sees it, rendered formulas shown as [math], cut around the trouble.
    const copy = b.cloneNode(true);
    for (const k of copy.querySelectorAll('.katex-display, .katex')) {
      if (copy.contains(k)) k.replaceWith(document.createTextNode('[math]'));
    }
    const ctx = copy.textContent.replace(/\s+/g, ' ').trim();
    const at = Math.max(0, (dollar ? ctx.search(/\$|\\[()[\]]/) : ctx.search(/\\[A-Za-z]/)) - 80);
    const cut = ctx.slice(at, at + 240);
    (dollar ? out.stray : out.texOutside).push((at > 0 ? '...' : '') + cut + (at + 240 < ctx.length ? '...' : ''));
  }
  return out;
}

// Problems KaTeX's input shows by itself, whatever the source.
function lintRendered(tex) {
  const issues = [];
  const sub = /\\(?:math(?:rm|it|sf|tt|bf)|operatorname|text\w*)\{(?:[^{}\\_]|\\.)*_/.exec(tex);
  if (sub) issues.push(`\`_\` inside \`${sub[0].split('{')[0]}{...}\`: Markdown ate the backslash of \`\\_\` (write \`\\\\_\` for a literal underscore)`);
  const smart = tex.match(/[\u2018\u2019\u201c\u201d\u2013\u2014\u2026]/g);
  if (smart) issues.push(`smart punctuation inside math (${[...new Set(smart)].join(' ')}): Markdown changed \`'\`, \`"\`, \`--\` or \`...\``);
  const env = /\\begin\{(cases|dcases|rcases|aligned|align\*?|alignat\*?|gathered|gather\*?|split|eqnarray\*?)\}([\s\S]*?)\\end\{\1\}/g;
  let m;
  while ((m = env.exec(tex))) {
    if (!/\\\\|\\cr\b/.test(m[2])) issues.push(`\`${m[1]}\` environment without a row break: Markdown made \`\\\\\` into \`\\\` (write \`\\\\\\\\\`)`);
  }
  return issues;
}

// ---------------------------------------------------------------------------------------------
async function main() {
  const t0 = Date.now();
  const pages = walk(args.doc, '.html')
    .filter((p) => !/http-equiv="refresh"/.test(fs.readFileSync(p, 'utf8').slice(0, 2000)));
  if (pages.length === 0) die(`no pages under ${args.doc}`);
  const userDir = fs.mkdtempSync(path.join(require('os').tmpdir(), 'check-math-chromium-'));
  const browser = new Browser(args.chromium, userDir);
  const stats = { katexServed: 0 };
  const report = { pages: 0, formulas: 0, traced: 0, errors: [], untraced: [], blocked: new Set() };
  // One entry per formula (or unrendered passage), with its problems, pages and source lines.
  const byText = new Map();
  const addError = (page, text, problem, where) => {
    if (!byText.has(text)) {
      byText.set(text, { text, problems: [], where: new Set(), pages: new Set() });
      report.errors.push(byText.get(text));
    }
    const e = byText.get(text);
    if (!e.problems.includes(problem)) e.problems.push(problem);
    if (where) e.where.add(where);
    e.pages.add(page);
  };
  // The doc comment(s) a formula as KaTeX got it came from, with what Markdown did to them.
  const trace = (page, tex, shown) => {
    const src = sources.get(norm(unSmart(tex)));
    if (!src) return null;
    for (const s of src) {
      s.seen = true;
      for (const i of s.issues) addError(page, shown, i, s.where);
    }
    return src;
  };
  try {
    const tabs = [];
    const nTabs = args.shots ? 1 : 2;
    for (let i = 0; i < nTabs; i++) tabs.push(await openTab(browser, stats));
    const queue = args.pages.length ? args.pages.map((p) => path.join(args.doc, p)) : pages.slice();
    for (const p of queue) if (!fs.existsSync(p)) die(`no page ${p}`);
    if (args.shots) fs.mkdirSync(args.shots, { recursive: true });
    const root = path.dirname(args.doc);
    await Promise.all(tabs.map(async (tab) => {
      for (let file; (file = queue.shift());) {
        const page = path.relative(root, file);
        await load(tab, 'file://' + file);
        if (args.shots) {
          await tab.send('Runtime.evaluate', { expression: 'document.fonts.ready.then(() => 1)', awaitPromise: true });
          const { cssContentSize } = await tab.send('Page.getLayoutMetrics');
          const height = Math.min(Math.ceil(cssContentSize.height), 6000);
          const shot = await tab.send('Page.captureScreenshot', {
            format: 'png', captureBeyondViewport: true, clip: { x: 0, y: 0, width: 1280, height, scale: 1 },
          });
          const out = path.join(args.shots, page.replace(/\//g, '__').replace(/\.html$/, '.png'));
          fs.writeFileSync(out, Buffer.from(shot.data, 'base64'));
          console.log(`screenshot ${out} (${height} px high)`);
          // The same page in parts of the text column, readable at a viewer's size.
          for (let y = 0, k = 1; y < height && k <= 8; y += 800, k++) {
            const part = await tab.send('Page.captureScreenshot', {
              format: 'png', captureBeyondViewport: true,
              clip: { x: 220, y, width: 1020, height: Math.min(800, height - y), scale: 1 },
            });
            fs.writeFileSync(out.replace(/\.png$/, `.part${k}.png`), Buffer.from(part.data, 'base64'));
          }
        }
        const { result, exceptionDetails } = await tab.send('Runtime.evaluate', {
          expression: `(${inspectPage.toString()})()`, returnByValue: true,
        });
        if (exceptionDetails) die(`inspecting ${page}: ${exceptionDetails.text}`);
        const r = result.value;
        report.pages++;
        tab.blocked.filter((u) => !/\/katex@/.test(u)).forEach((u) => report.blocked.add(u));
        // Offline, KaTeX must not reach for its CDN (a crate's own favicon or logo is only noted).
        if (args.offline) tab.blocked.filter((u) => /\/katex@/.test(u)).forEach((u) => addError(page, '(network)', `KaTeX requested from the network, offline: ${u}`));
        if (!r.katex) addError(page, '(whole page)', `KaTeX did not load: no window.katex (header missing, or ${args.offline ? 'its local copy missing' : 'its CDN not answered'})`);
        if (args.offline) {
          // The fonts a page's formulas use, once loaded: from the local copy, or failed.
          const { result: fonts } = await tab.send('Runtime.evaluate', {
            expression: 'document.fonts.ready.then(() => [...document.fonts].filter((f) => /KaTeX/.test(f.family)).map((f) => f.status))',
            awaitPromise: true, returnByValue: true,
          });
          const status = fonts.value || [];
          if (status.includes('error')) addError(page, '(whole page)', 'a KaTeX font failed to load from the local copy');
          if (r.formulas.length && !status.includes('loaded')) addError(page, '(whole page)', 'no KaTeX font loaded for its formulas');
        }
        const failed = [];
        for (const c of tab.console) {
          const m = /KaTeX auto-render: Failed to parse `([\s\S]*)` with\s*([\s\S]*)/.exec(c.text);
          if (m) failed.push({ tex: m[1], message: m[2].split('\n')[0] });
          else if (c.type === 'exception' || (c.type === 'error' && /katex/i.test(c.text))) addError(page, '(script)', c.text.split('\n')[0]);
        }
        for (const e of r.errors) failed.push({ tex: e.tex, message: e.message });
        for (const f of failed) {
          const shown = `$${f.tex}$`;
          addError(page, shown, `KaTeX cannot parse it: ${f.message}`);
          (trace(page, f.tex, shown) || []).forEach((x) => byText.get(shown).where.add(x.where));
        }
        for (const s of r.stray) {
          // A formula KaTeX could not parse stays as its source, delimiters and all: said above.
          let rest = s;
          for (const f of failed) rest = rest.split(`$$${f.tex}$$`).join('').split(`$${f.tex}$`).join('');
          if (rest.includes('$') || /\\[()[\]]/.test(rest)) addError(page, s, 'math delimiters left in the text: the formula was not rendered (Markdown split it, e.g. `*` or `_` read as emphasis, or a `$` is unmatched)');
        }
        for (const s of r.texOutside) addError(page, s, 'a TeX command in the text outside math: not rendered');
        for (const f of r.formulas) {
          report.formulas++;
          const shown = f.display ? `$$${f.tex}$$` : `$${f.tex}$`;
          const src = trace(page, f.tex, shown);
          if (src) report.traced++;
          else report.untraced.push({ page, tex: f.tex });
          // What the source says is the sharper message (it names the fix); the rendered text
          // speaks for formulas whose source is clean or not found.
          const rendered = src && src.some((x) => x.issues.length) ? [] : lintRendered(f.tex);
          for (const i of rendered) addError(page, shown, i);
          if (src && byText.has(shown)) src.forEach((x) => byText.get(shown).where.add(x.where));
          // Strict mode complains about the curly quotes too: said once already.
          if (f.strict && !/Unrecognized Unicode character "[\u2018\u2019\u201c\u201d\u2013\u2014\u2026]"/.test(f.strict)) {
            addError(page, shown, `not valid LaTeX (KaTeX strict mode): ${f.strict}`);
          }
        }
      }
    }));
  } finally {
    await browser.close();
    fs.rmSync(userDir, { recursive: true, force: true, maxRetries: 3 });
  }

  // Summary
  const secs = ((Date.now() - t0) / 1000).toFixed(1);
  console.log(`check-math: ${report.pages} pages, ${report.formulas} formulas rendered ` +
    `(${report.traced} traced to a doc comment; ${allSources.length} formulas written in src/), ` +
    `KaTeX files served locally: ${stats.katexServed}, ${secs} s`);
  if (report.blocked.size) console.log(`  note: refused ${report.blocked.size} other network request(s): ${[...report.blocked].slice(0, 5).join(', ')}`);
  const unseen = allSources.filter((s) => !s.seen && s.issues.length);
  if (unseen.length) {
    console.log(`  note: ${unseen.length} formula(s) with Markdown problems in doc comments that no page shows rendered (private items, or a formula Markdown split: see the errors below):`);
    for (const s of unseen) {
      const d = s.display ? '$$' : '$';
      console.log(`    ${s.where}: ${d}${s.tex.replace(/\s+/g, ' ')}${d}`);
      for (const i of s.issues) console.log(`      - ${i}`);
    }
  }
  if (report.untraced.length) {
    console.log(`  note: ${report.untraced.length} rendered formula(s) not traced to a doc comment (checked on the page only):`);
    for (const u of report.untraced.slice(0, 10)) console.log(`    ${u.page}: ${u.tex.replace(/\s+/g, ' ')}`);
  }
  for (const e of report.errors) {
    const pages = [...e.pages];
    const where = e.where.size ? ` (${[...e.where].join(', ')})` : '';
    console.log(`ERROR ${pages.slice(0, 3).join(', ')}${pages.length > 3 ? ` and ${pages.length - 3} more` : ''}${where}`);
    console.log(`  ${e.text.replace(/\s+/g, ' ')}`);
    for (const p of e.problems) console.log(`  - ${p}`);
  }
  console.log(`check-math: ${report.errors.length} error(s)`);
  process.exit(report.errors.length ? 1 : 0);
}

main().catch((e) => die(e.stack || String(e)));
