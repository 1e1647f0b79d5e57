"""Jupyter's picture of a network: an SVG graph of its nodes and wires (a geometry draws itself as a PNG, natively)."""

from __future__ import annotations

import html
import json
from typing import Any


def network_svg(document: str) -> str:
    """The top-level nodes as boxes (name and type) joined by their wires,
    drawn over the boxes so a wire passing a node is not taken for its input.

    Nodes are placed where the studio saved them, else in rows by how far
    they are from the network's sources, as Houdini lays out a new network.
    """
    doc = json.loads(document)
    nodes: dict[str, Any] = doc.get("nodes", {})
    output = doc.get("output")
    pos = _layout(nodes)
    w, h, pad = 130, 34, 20
    xs = [p[0] for p in pos.values()] or [0]
    ys = [p[1] for p in pos.values()] or [0]
    x0, y0 = min(xs), min(ys)
    width = max(xs) - x0 + w + 2 * pad
    height = max(ys) - y0 + h + 2 * pad
    at = {n: (p[0] - x0 + pad, p[1] - y0 + pad) for n, p in pos.items()}
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0f}" height="{height:.0f}" font-family="sans-serif">',
             f'<rect width="{width:.0f}" height="{height:.0f}" fill="#1e1e1e"/>']
    for name, node in nodes.items():
        x, y = at[name]
        edge = "#4fc3f7" if name == output or node.get("display") else "#666"
        fill = "#5a4a2a" if node.get("bypass") else "#3a3a3a"
        parts.append(f'<rect x="{x:.1f}" y="{y:.1f}" width="{w}" height="{h}" rx="5" fill="{fill}" stroke="{edge}" stroke-width="2"/>')
        ins = node.get("inputs", [])
        for k in range(len(ins)):
            parts.append(f'<circle cx="{x + w * (k + 1) / (len(ins) + 1):.1f}" cy="{y:.1f}" r="3" fill="#ddd"/>')
        parts.append(f'<text x="{x + 8:.1f}" y="{y + 15:.1f}" fill="#eee" font-size="12">{html.escape(name)}</text>')
        parts.append(f'<text x="{x + 8:.1f}" y="{y + 28:.1f}" fill="#aaa" font-size="10">{html.escape(str(node.get("type", "")))}</text>')
    for name, node in nodes.items():
        ins = node.get("inputs", [])
        for k, src in enumerate(ins):
            if src is None or src not in at:
                continue
            sx, sy = at[src]
            tx, ty = at[name]
            tx += w * (k + 1) / (len(ins) + 1)
            parts.append(f'<path d="M{sx + w / 2:.1f} {sy + h:.1f}C{sx + w / 2:.1f} {sy + h + 20:.1f} {tx:.1f} {ty - 20:.1f} {tx:.1f} {ty:.1f}" fill="none" stroke="#9a9a9a" stroke-opacity="0.8" stroke-width="1.5"/>')
    parts.append("</svg>")
    return "".join(parts)


def _layout(nodes: dict[str, Any]) -> dict[str, tuple[float, float]]:
    saved = {n: tuple(v["ui"]["pos"]) for n, v in nodes.items() if isinstance(v.get("ui"), dict) and "pos" in v["ui"]}
    if len(saved) == len(nodes):
        return {n: (p[0], p[1]) for n, p in saved.items()}
    depth: dict[str, int] = {}
    for _ in range(len(nodes) + 1):  # longest path from a source, without recursion
        changed = False
        for name, node in nodes.items():
            d = 1 + max((depth.get(s, 0) for s in node.get("inputs", []) if s in nodes), default=-1)
            if depth.get(name) != d:
                depth[name], changed = d, True
        if not changed:
            break
    # Then each node as low as its readers allow (a source sits just above
    # the node that reads it, not at the top of a long chain's row).
    readers: dict[str, list[str]] = {n: [] for n in nodes}
    for name, node in nodes.items():
        for s in node.get("inputs", []):
            if s in readers:
                readers[s].append(name)
    for name in sorted(nodes, key=lambda n: -depth.get(n, 0)):
        below = [depth[r] for r in readers[name] if r in depth]
        if below:
            depth[name] = max(depth.get(name, 0), min(below) - 1)
    rows: dict[int, list[str]] = {}
    for name in nodes:
        rows.setdefault(depth.get(name, 0), []).append(name)
    # Each row ordered by where its inputs sit (a barycentre sweep, as the
    # studio's layout does), so that wires run down rather than across.
    column: dict[str, float] = {}
    for d in sorted(rows):
        def centre(name: str) -> float:
            xs = [column[s] for s in nodes[name].get("inputs", []) if s in column]
            return sum(xs) / len(xs) if xs else float("inf")

        rows[d].sort(key=centre)
        for i, name in enumerate(rows[d]):
            column[name] = float(i)
    # Then upwards, each row by where it is read: a node feeding input 0
    # left of one feeding input 1 of the same reader, so wires do not cross.
    for d in sorted(rows, reverse=True)[1:]:
        def slot(name: str) -> float:
            at = [
                column[r] + (k + 1) / (len(nodes[r].get("inputs", [])) + 1)
                for r in readers[name]
                if r in column
                for k, s in enumerate(nodes[r].get("inputs", []))
                if s == name
            ]
            return sum(at) / len(at) if at else column[name]

        rows[d].sort(key=slot)
        for i, name in enumerate(rows[d]):
            column[name] = float(i)
    return {n: (i * 160.0, d * 70.0) for d, names in rows.items() for i, n in enumerate(names)}
