// The golden-image report's behaviour (inlined into the page by report.py): zoom to single
// pixels, the slider and blink comparison of expected and actual, scrolling the pictures
// together, the pixel read-out and the copy button. No libraries and no network.
"use strict";

const BLINK_MS = 700;

for (const card of document.querySelectorAll("article.failure")) {
  setUpFailure(card);
}

function setUpFailure(card) {
  const images = Array.from(card.querySelectorAll("img"));
  const zoomSelect = card.querySelector("select.zoom");
  const expected = card.querySelector("figure.expected img");
  const actual = card.querySelector("figure.actual img");

  // Zoom: every picture of the card at the same integer scale, drawn pixelated.
  function setZoom(zoom) {
    card.dataset.zoom = String(zoom);
    for (const img of images) {
      if (img.naturalWidth > 0) {
        img.style.width = img.naturalWidth * zoom + "px";
        img.style.height = img.naturalHeight * zoom + "px";
      }
    }
    const range = card.querySelector("input.split");  // the slider as wide as the picture it splits
    const stack = card.querySelector(".stack");
    if (range && stack) range.style.width = Math.max(120, Math.min(stack.parentElement.clientWidth, stack.offsetWidth)) + "px";
  }
  zoomSelect.addEventListener("change", () => setZoom(Number(zoomSelect.value)));
  Promise.all(images.map((img) => img.decode().catch(() => null))).then(() => {
    // Small images open enlarged (about 320 pixels wide), large ones at 1×.
    const width = (expected || actual || images[0] || { naturalWidth: 320 }).naturalWidth || 320;
    const choices = Array.from(zoomSelect.options).map((o) => Number(o.value));
    const wanted = Math.max(1, Math.floor(320 / width));
    const zoom = choices.filter((z) => z <= wanted).pop() || 1;
    zoomSelect.value = String(zoom);
    setZoom(zoom);
  });

  // Scrolling one picture scrolls the others to the same place.
  const views = Array.from(card.querySelectorAll(".view"));
  let syncing = false;
  for (const view of views) {
    view.addEventListener("scroll", () => {
      if (syncing) return;
      syncing = true;
      for (const other of views) {
        if (other !== view) {
          other.scrollLeft = view.scrollLeft;
          other.scrollTop = view.scrollTop;
        }
      }
      syncing = false;
    });
  }

  setUpCompare(card);
  setUpPixelReadout(card, images, expected, actual);

  const copy = card.querySelector("button.copy");
  if (copy) {
    copy.addEventListener("click", () => {
      const text = card.querySelector("code.command").textContent;
      const done = () => { copy.textContent = "copied"; };
      const select = () => {  // file:// pages may have no clipboard API: select the text instead
        const range = document.createRange();
        range.selectNodeContents(card.querySelector("code.command"));
        getSelection().removeAllRanges();
        getSelection().addRange(range);
        copy.textContent = "selected: press Ctrl+C";
      };
      if (navigator.clipboard) navigator.clipboard.writeText(text).then(done, select);
      else select();
    });
  }
}

function setUpCompare(card) {
  const compare = card.querySelector(".compare");
  if (!compare) return;
  const over = compare.querySelector("img.over");  // the actual image, on top of the expected one
  const line = compare.querySelector(".split-line");
  const range = compare.querySelector("input.split");
  const showing = compare.querySelector(".showing");
  let timer = null;

  function showSplit() {
    const position = Number(range.value);
    over.style.visibility = "visible";
    over.style.clipPath = `inset(0 ${100 - position}% 0 0)`;  // actual left of the line
    line.style.left = position + "%";
    showing.textContent = "left of the line: actual · right: expected";
    compare.dataset.showing = position >= 100 ? "actual" : position <= 0 ? "expected" : "both";
  }
  function showWhole(which) {
    over.style.clipPath = "none";
    over.style.visibility = which === "actual" ? "visible" : "hidden";
    showing.textContent = "showing: " + which;
    compare.dataset.showing = which;
  }
  function setMode(mode) {
    compare.dataset.mode = mode;
    for (const radio of compare.querySelectorAll("input[type=radio]")) radio.checked = radio.value === mode;
    clearInterval(timer);
    timer = null;
    if (mode === "blink") {
      showWhole("expected");
      timer = setInterval(() => showWhole(compare.dataset.showing === "actual" ? "expected" : "actual"), BLINK_MS);
    } else {
      showSplit();
    }
  }
  for (const radio of compare.querySelectorAll("input[type=radio]")) {
    radio.addEventListener("change", () => setMode(radio.value));
  }
  range.addEventListener("input", showSplit);
  setMode("slider");
}

function setUpPixelReadout(card, images, expected, actual) {
  const out = card.querySelector(".pixel");
  if (!expected && !actual) return;
  const pixels = new Map();  // img → its RGBA bytes (read once, on first use)

  function read(img) {
    if (!img || img.naturalWidth === 0) return null;
    if (!pixels.has(img)) {
      const canvas = document.createElement("canvas");
      canvas.width = img.naturalWidth;
      canvas.height = img.naturalHeight;
      const context = canvas.getContext("2d", { willReadFrequently: true });
      context.drawImage(img, 0, 0);
      pixels.set(img, { width: canvas.width, height: canvas.height, data: context.getImageData(0, 0, canvas.width, canvas.height).data });
    }
    return pixels.get(img);
  }
  function value(image, row, col) {
    if (!image || row >= image.height || col >= image.width) return null;
    const i = 4 * (row * image.width + col);
    return Array.from(image.data.slice(i, i + 4));
  }
  for (const img of images) {
    img.addEventListener("mousemove", (event) => {
      const zoom = Number(card.dataset.zoom || 1);
      const col = Math.floor(event.offsetX / zoom);
      const row = Math.floor(event.offsetY / zoom);
      const e = value(read(expected), row, col);
      const a = value(read(actual), row, col);
      if (!e && !a) return;
      let text = `row ${row}, col ${col}: expected ${e ? e.join(" ") : "–"} · actual ${a ? a.join(" ") : "–"}`;
      if (e && a) text += " · difference " + a.map((v, k) => v - e[k]).map((d) => (d > 0 ? "+" : "") + d).join(" ");
      out.textContent = text + " (RGBA, /255)";
    });
  }
}
