// Typeset every rustdoc page of the crate with the header's own script in jsdom and count what
// stays raw (delimiters or TeX commands left in the text), what rustdoc corrupted (curly quotes,
// dashes, ellipses inside a formula: its smart punctuation), and what KaTeX cannot parse.
// Usage (see README of this folder): node check.js DOC_DIR HEADER_HTML; exit 1 on any finding.
"use strict";
const fs = require("fs");
const path = require("path");
const { JSDOM, VirtualConsole } = require("jsdom");

const [docDir, headerFile] = process.argv.slice(2);
if (!docDir || !headerFile) {
  console.error("usage: node check.js DOC_DIR HEADER_HTML");
  process.exit(2);
}
const dist = path.join(__dirname, "node_modules/katex/dist");
const katexSrc = fs.readFileSync(path.join(dist, "katex.min.js"), "utf8");
const autoSrc = fs.readFileSync(path.join(dist, "contrib/auto-render.min.js"), "utf8");
const inline = fs.readFileSync(headerFile, "utf8").match(/<script>([\s\S]*?)<\/script>/)[1];

function pages(dir) {
  let out = [];
  for (const e of fs.readdirSync(dir, { withFileTypes: true })) {
    const p = path.join(dir, e.name);
    if (e.isDirectory()) {
      // Source listings are <pre> and are never typeset.
      if (e.name !== "src" && e.name !== "static.files") out = out.concat(pages(p));
    } else if (e.name.endsWith(".html")) {
      out.push(p);
    }
  }
  return out;
}

const skip = new Set(["CODE", "PRE", "SCRIPT", "STYLE", "TEXTAREA", "NOSCRIPT"]);
const total = { pages: 0, rendered: 0, errors: 0, raw: 0, corrupted: 0 };
const seen = new Set();
for (const file of pages(docDir)) {
  const dom = new JSDOM(fs.readFileSync(file, "utf8"), {
    runScripts: "outside-only",
    virtualConsole: new VirtualConsole(),
  });
  const w = dom.window;
  w.eval(katexSrc);
  w.eval(autoSrc);
  w.eval(inline);
  w.document.dispatchEvent(new w.Event("DOMContentLoaded"));
  total.pages++;
  const rel = path.relative(docDir, file);
  const report = (kind, text) => {
    const key = kind + text;
    if (!seen.has(key)) {
      seen.add(key);
      console.log(`${kind.padEnd(9)} ${rel} | ${text.replace(/\s+/g, " ").slice(0, 160)}`);
    }
  };
  for (const a of w.document.querySelectorAll("annotation[encoding='application/x-tex']")) {
    total.rendered++;
    if (/[’‘“”–—…]/.test(a.textContent)) {
      total.corrupted++;
      report("CORRUPTED", a.textContent);
    }
  }
  for (const e of w.document.querySelectorAll(".katex-error")) {
    total.errors++;
    report("ERROR", `${e.getAttribute("title")} :: ${e.textContent}`);
  }
  const walker = w.document.createTreeWalker(w.document.body, w.NodeFilter.SHOW_TEXT);
  for (let n = walker.nextNode(); n; n = walker.nextNode()) {
    let p = n.parentElement;
    let inside = false;
    for (; p; p = p.parentElement) {
      if (skip.has(p.tagName) || p.classList.contains("katex")) {
        inside = true;
        break;
      }
    }
    if (!inside && /\$|\\[A-Za-z]+|\\[,;!{}]/.test(n.textContent)) {
      total.raw++;
      report("RAW", n.textContent);
    }
  }
}
console.log(JSON.stringify(total));
process.exit(total.errors + total.raw + total.corrupted > 0 ? 1 : 0);
