// One style for every worked solution, and the checks out of the reader's way.
//
// * Solutions: a sphinx-exercise solution block (its title "Solution to Exercise 5.2"
//   becomes the summary) and each run of code cells tagged `solution` outside such a
//   block are folded into one closed <details class="robokin-solution">, so a student
//   reads the task before the answer.
// * Checks: each run of code cells tagged `check` (the asserts that test the computed
//   numbers against independent values) is folded into a closed
//   <details class="robokin-checks">: the notebooks keep them, the reading is not
//   interrupted by them.
document.addEventListener("DOMContentLoaded", function () {
  function fold(first, run, className, summaryNode) {
    var details = document.createElement("details");
    details.className = className;
    var summary = document.createElement("summary");
    summary.appendChild(summaryNode);
    details.appendChild(summary);
    first.parentNode.insertBefore(details, first);
    run.forEach(function (c) { details.appendChild(c); });
    return details;
  }

  function foldRuns(selector, className, label, skipInside) {
    var seen = new Set();
    Array.prototype.slice.call(document.querySelectorAll(selector)).forEach(function (cell) {
      if (seen.has(cell) || (skipInside && cell.closest(skipInside))) { return; }
      var run = [cell];
      var next = cell.nextElementSibling;
      while (next && next.matches(selector)) { run.push(next); next = next.nextElementSibling; }
      run.forEach(function (c) { seen.add(c); });
      var text = label + (run.length > 1 ? " (" + run.length + " cells)" : "") + " (click to show)";
      fold(cell, run, className, document.createTextNode(text));
    });
  }

  // sphinx-exercise solutions: the title (with its link to the exercise) is the summary.
  Array.prototype.slice.call(document.querySelectorAll("div.solution.admonition")).forEach(function (box) {
    if (box.closest("details.robokin-solution")) { return; }
    var title = box.querySelector(":scope > p.admonition-title");
    var label = document.createElement("span");
    if (title) {
      while (title.firstChild) { label.appendChild(title.firstChild); }
      title.remove();
    } else {
      label.textContent = "Solution";
    }
    label.appendChild(document.createTextNode(" (click to show)"));
    fold(box, [box], "robokin-solution", label);
  });
  foldRuns("div.cell.tag_solution", "robokin-solution", "Solution", "details.robokin-solution");
  foldRuns("div.cell.tag_check", "robokin-checks", "Checks", null);
});
