"""Writing an inferred machine so a person can see what each state means.

:func:`write_results` (``learner``, ``machine.json``) writes, all atomically:

* ``machine.json``: the reward machine (shaped when the learner has ``gamma``; the versioned
  automaton JSON ``symlearn automaton show`` reads);
* ``machine.labeling.json`` (+ ``machine.labeling.features.safetensors``): the labeling, to label
  new frames with the machine's propositions;
* ``machine.prototypes/u<k>.png``: the prototype frame of every state;
* ``machine.dot`` (or ``dot=``): the machine with each state drawn as its prototype image
  (Graphviz ``image`` attributes with paths relative to the DOT file; self-loops left out);
* ``machine.prototypes.png``: all prototypes in a grid (matplotlib), and ``machine.md``, a
  markdown report with that grid, the states, the transitions and the parameters found.
"""

from __future__ import annotations

import io
import os
from pathlib import Path

import numpy as np

from symlearn.atomic import write_bytes, write_text
from symlearn.rendering import quote


def _png(image: np.ndarray, scale: int = 3) -> bytes:
    import matplotlib.image as mpimg

    big = np.repeat(np.repeat(np.asarray(image), scale, axis=0), scale, axis=1)
    buffer = io.BytesIO()
    mpimg.imsave(buffer, big.squeeze() if big.shape[-1] == 1 else big, format="png")
    return buffer.getvalue()


def transitions_table(machine) -> list[tuple[int, str, int, float]]:
    """``(source, proposition read, target, reward)`` of every edge between different states."""
    rows = []
    for u in range(machine.n_states):
        for guard, v, reward in machine.successors(u):
            if v != u:
                positive = sorted(p for c in guard.cubes() for p, value in c.items() if value)
                rows.append((u, " | ".join(positive) or str(guard), v, float(reward)))
    return rows


def machine_dot(machine, images: dict[int, str] | None = None, title: str = "") -> str:
    """DOT of the machine: states as prototype images (when given), edges labelled by the proposition read."""
    lines = ["digraph machine {", "  rankdir=LR;", '  node [shape=box, fontname="Helvetica"];',
             f"  label={quote(title + ' (self-loops omitted)')}; labelloc=t;"]
    for u in range(machine.n_states):
        attributes = [f"label={quote(f'u{u}')}"]
        if images and u in images:
            attributes += [f"image={quote(images[u])}", "labelloc=b", "imagescale=true", "width=1.3", "height=1.5",
                           "fixedsize=true"]
        if u in machine.accepting:
            attributes.append("peripheries=2")
        lines.append(f"  u{u} [{', '.join(attributes)}];")
    lines.append('  start [shape=point]; start -> u0;'.replace("u0", f"u{machine.initial}"))
    for u, read, v, reward in transitions_table(machine):
        lines.append(f"  u{u} -> u{v} [label={quote(f'{read} / {reward:.3g}')}];")
    lines.append("}")
    return "\n".join(lines) + "\n"


def prototype_grid(images: np.ndarray, titles: list[str]) -> bytes:
    """A PNG of the images in a grid with titles (matplotlib, Agg)."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    n = len(images)
    columns = min(n, 4)
    rows = -(-n // columns)
    figure, axes = plt.subplots(rows, columns, figsize=(2.4 * columns, 2.6 * rows), squeeze=False)
    for k, axis in enumerate(axes.flat):
        axis.axis("off")
        if k < n:
            axis.imshow(images[k].squeeze(), interpolation="nearest")
            axis.set_title(titles[k], fontsize=9)
    figure.tight_layout()
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=90)
    plt.close(figure)
    return buffer.getvalue()


def write_results(learner, path: str | os.PathLike[str], *, dot: str | os.PathLike[str] | None = None,
                  title: str = "inferred reward machine", source: str = "") -> list[Path]:
    """Write the machine, labeling, prototypes, DOT, grid and report (see the module docstring)."""
    learner.check_fitted()
    path = Path(path)
    stem = path.with_suffix("")
    machine = learner.shaped_machine_ or learner.machine_
    written = [learner.save(path)]  # the machine (shaped when it was): the learner's own file
    written += learner.labeling_.save(stem.with_name(stem.name + ".labeling.json"))
    folder = stem.with_name(stem.name + ".prototypes")
    folder.mkdir(parents=True, exist_ok=True)
    images = {}
    for k, image in enumerate(learner.prototype_frames_):
        written.append(write_bytes(folder / f"u{k}.png", _png(image)))
        images[k] = f"{folder.name}/u{k}.png"
    dot_path = Path(dot) if dot is not None else stem.with_suffix(".dot")
    relative = {k: os.path.relpath(folder / f"u{k}.png", dot_path.parent) for k in images}
    written.append(write_text(dot_path, machine_dot(machine, relative, title)))
    grid = stem.with_name(stem.name + ".prototypes.png")
    records = learner.result_.history
    written.append(write_bytes(grid, prototype_grid(learner.prototype_frames_,
                                                    [f"u{r.state}: {r.proposition} ({r.frames} frames)" for r in records])))
    metrics = learner.result_.metrics
    lines = [f"# {title}", ""]
    if source:
        lines += [f"Demonstrations: `{source}` ({metrics['frames']} frames, {len(learner.lengths_)} videos).", ""]
    lines += [f"![prototypes]({grid.name})", "",
              "| state | proposition | frames in its cluster | prototype (video, frame) |", "|---|---|---|---|"]
    lines += [f"| u{r.state}{' (start)' if r.state == machine.initial else ''}"
              f"{' (goal)' if r.state in machine.accepting else ''} | {r.proposition} | {r.frames} | "
              f"({r.prototype_demonstration}, {r.prototype_frame}) |" for r in records]
    lines += ["", "| from | reads | to | reward |", "|---|---|---|---|"]
    lines += [f"| u{u} | {read} | u{v} | {reward:.4g} |" for u, read, v, reward in transitions_table(machine)]
    lines += ["", "Parameters (derived from the data unless given):", "",
              f"* eps = {metrics['eps']:.4g} ({metrics['defaults.eps_source']}), min_samples = "
              f"{metrics['min_samples']} ({metrics['defaults.min_samples_source']})",
              f"* kappa = {metrics['kappa']:.4g}; frames with several propositions: {metrics['multiple_label_frames']}",
              f"* features: {metrics['features']}",
              f"* clusters: {metrics['clusters']} (dropped: {metrics['dropped_clusters']}), clustered frames: "
              f"{metrics['clustered_frames']} of {metrics['frames']}",
              f"* time: {learner.result_.timings['total']:.2f} s", "",
              f"Files: `{path.name}` (machine), `{dot_path.name}` (DOT with the prototypes as states), "
              f"`{stem.name}.labeling.json` (labeling), `{folder.name}/` (prototype images)."]
    written.append(write_text(stem.with_suffix(".md"), "\n".join(lines) + "\n"))
    return written


__all__ = ["machine_dot", "prototype_grid", "transitions_table", "write_results"]
