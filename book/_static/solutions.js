// Collapse worked solutions: code cells tagged `solution` that are not already
// inside a sphinx-exercise solution dropdown are wrapped, run by run, in a
// closed <details> element, so a student reads the task before the answer.
document.addEventListener("DOMContentLoaded", function () {
  var cells = Array.prototype.slice.call(document.querySelectorAll("div.cell.tag_solution"));
  var seen = new Set();
  cells.forEach(function (cell) {
    if (seen.has(cell) || cell.closest(".solution")) { return; }
    var run = [cell];
    var next = cell.nextElementSibling;
    while (next && next.matches("div.cell.tag_solution")) { run.push(next); next = next.nextElementSibling; }
    run.forEach(function (c) { seen.add(c); });
    var details = document.createElement("details");
    details.className = "robokin-solution";
    var summary = document.createElement("summary");
    summary.textContent = "Solution (click to show)";
    details.appendChild(summary);
    cell.parentNode.insertBefore(details, cell);
    run.forEach(function (c) { details.appendChild(c); });
  });
});
