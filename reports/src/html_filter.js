// The HTML report's vector filter (reports/src/html.cpp). Embedded by
// reports/CMakeLists.txt; the page's Content-Security-Policy allows this
// script by its SHA-256 and no other. A query string sets the filter, so a
// filtered view can be linked: report.html?status=fail&level=must&paragraph=3.2
(() => {
  'use strict';
  const form = document.getElementById('filter');
  if (!form) return;
  const vectors = Array.from(document.querySelectorAll('#vectors details.v'));
  const keys = ['status', 'level', 'paragraph'];
  const shown = document.getElementById('shown');
  const apply = () => {
    let count = 0;
    for (const v of vectors) {
      const match = keys.every((k) => form.elements[k].value === '' || v.dataset[k] === form.elements[k].value);
      v.hidden = !match;
      if (match) count += 1;
    }
    shown.textContent = `${count} of ${vectors.length} vectors shown`;
    form.dataset.shown = String(count);
  };
  const query = new URLSearchParams(window.location.search);
  for (const k of keys) {
    const want = query.get(k);
    if (want !== null && Array.from(form.elements[k].options).some((o) => o.value === want)) form.elements[k].value = want;
  }
  form.addEventListener('change', apply);
  form.hidden = false;
  apply();
})();
