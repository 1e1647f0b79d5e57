// What the viewport can draw over a result, as Houdini's display options do: points on meshes, normals as short lines, point and primitive numbers as labels (at most LABEL_LIMIT, nearest the camera first), and the picked element's marker.

import * as THREE from 'three';
import type { GeometryPart } from './protocol';

/** The most numbers drawn at once (Houdini too thins them out when dense). */
export const LABEL_LIMIT = 1500;
/** The most normals drawn (every k-th beyond). */
export const NORMAL_LIMIT = 200_000;

export interface DisplayOptions {
  points: boolean;
  normals: boolean;
  pointNumbers: boolean;
  primNumbers: boolean;
}

/** Every point of a part as a dot. */
export function pointsOverlay(part: GeometryPart, material: THREE.PointsMaterial): THREE.Points | null {
  if (!part.positions?.length) return null;
  const geo = new THREE.BufferGeometry();
  geo.setAttribute('position', new THREE.BufferAttribute(part.positions, 3));
  return new THREE.Points(geo, material);
}

/** A line from each point (or drawn corner) along its normal, `length` long. */
export function normalsOverlay(part: GeometryPart, length: number, material: THREE.LineBasicMaterial): THREE.LineSegments | null {
  const [pos, nrm] = part.cornerNormals && part.corners ? [part.corners, part.cornerNormals] : [part.positions, part.normals];
  if (!pos || !nrm) return null;
  const count = pos.length / 3;
  const step = Math.max(1, Math.ceil(count / NORMAL_LIMIT));
  const out = new Float32Array(Math.ceil(count / step) * 6);
  let j = 0;
  for (let i = 0; i < count; i += step, j += 6) {
    for (let k = 0; k < 3; k++) {
      out[j + k] = pos[i * 3 + k];
      out[j + 3 + k] = pos[i * 3 + k] + nrm[i * 3 + k] * length;
    }
  }
  const geo = new THREE.BufferGeometry();
  geo.setAttribute('position', new THREE.BufferAttribute(out, 3));
  return new THREE.LineSegments(geo, material);
}

/** Labels at 3D positions, drawn as HTML over the canvas: those in view, nearest first, at most LABEL_LIMIT. */
export class Labels {
  private host: HTMLElement;
  private pool: HTMLElement[] = [];

  constructor(parent: HTMLElement, className: string) {
    this.host = document.createElement('div');
    this.host.className = `labels ${className}`;
    parent.appendChild(this.host);
  }

  /** Shows `positions` (xyz triples) labelled by their index, as seen from `camera` in a `w` by `h` view. */
  update(positions: Float32Array | null, camera: THREE.Camera, w: number, h: number) {
    if (!positions) {
      this.host.hidden = true;
      return;
    }
    this.host.hidden = false;
    const v = new THREE.Vector3();
    const seen: [number, number, number, number][] = [];
    const camPos = new THREE.Vector3().setFromMatrixPosition(camera.matrixWorld);
    for (let i = 0; i < positions.length / 3; i++) {
      v.set(positions[i * 3], positions[i * 3 + 1], positions[i * 3 + 2]);
      const d = v.distanceToSquared(camPos);
      v.project(camera);
      if (v.z < -1 || v.z > 1 || Math.abs(v.x) > 1 || Math.abs(v.y) > 1) continue;
      seen.push([i, ((v.x + 1) / 2) * w, ((1 - v.y) / 2) * h, d]);
    }
    seen.sort((a, b) => a[3] - b[3]);
    const shown = seen.slice(0, LABEL_LIMIT);
    while (this.pool.length < shown.length) {
      const e = document.createElement('span');
      this.host.appendChild(e);
      this.pool.push(e);
    }
    this.pool.forEach((e, k) => {
      const s = shown[k];
      e.hidden = !s;
      if (!s) return;
      e.textContent = String(s[0]);
      e.style.transform = `translate(${s[1].toFixed(1)}px, ${s[2].toFixed(1)}px)`;
    });
  }

  /** How many labels are showing (for tests). */
  count(): number {
    return this.host.hidden ? 0 : this.pool.filter((e) => !e.hidden).length;
  }
}
