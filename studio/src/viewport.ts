// The 3D viewport (three.js): orbit, pan, zoom, frame all or selected; polygons smooth with N else flat, wireframe overlay, points, polylines, Cd; packed instances as GPU instances, or as points when there are too many triangles to draw.

import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import type { DecodedGeometry, GeometryPart } from './protocol';

/** While the camera moves, point clouds larger than this draw every k-th point (Houdini decimates while tumbling too). */
export const TUMBLE_POINTS = 100_000;

/** Instanced triangles above this are drawn as one point per instance (Houdini's point-cloud display of packed primitives). */
export const INSTANCE_TRIANGLE_BUDGET = 4_000_000;

export interface Drawn {
  generation: number;
  node: string;
  triangles: number;
  lines: number;
  points: number;
  instances: number;
  instancesAsPoints: boolean;
  /** A checksum of the drawn positions (changes when the geometry does). */
  checksum: number;
  /** Milliseconds from receiving the message to the first frame drawn with it. */
  drawMs: number;
  /** When that frame was drawn (performance.now()). */
  drawnAt: number;
}

/** A cheap, order-sensitive checksum of a float array (sampled for very large arrays). */
export function checksum(a: Float32Array): number {
  const step = Math.max(1, Math.floor(a.length / 200_000));
  let h = 2166136261;
  for (let i = 0; i < a.length; i += step) {
    h = Math.imul(h ^ Math.round(a[i] * 1e4), 16777619);
  }
  return (h ^ a.length) >>> 0;
}

export class Viewport {
  readonly renderer: THREE.WebGLRenderer;
  private scene = new THREE.Scene();
  private camera: THREE.PerspectiveCamera;
  private controls: OrbitControls;
  private content = new THREE.Group();
  private grid: THREE.GridHelper;
  private bounds: THREE.Box3 | null = null;
  private selection: THREE.Box3 | null = null;
  wireframe = false;
  forceFlat = false;
  drawn: Drawn | null = null;
  private last: DecodedGeometry | null = null;
  private needsRender = true;
  /** Full and decimated versions of large point clouds, swapped while tumbling. */
  private tumbleSwaps: { full: THREE.Object3D; light: THREE.Object3D }[] = [];
  /** Materials by their settings, kept across rebuilds (see `material`). */
  private materials = new Map<string, THREE.Material>();

  constructor(private host: HTMLElement) {
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(Math.min(2, window.devicePixelRatio));
    this.renderer.setClearColor(0x2b2f36);
    host.appendChild(this.renderer.domElement);
    this.camera = new THREE.PerspectiveCamera(45, 1, 0.01, 1e5);
    this.camera.position.set(4, 4.5, 6);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.addEventListener('change', () => (this.needsRender = true));
    this.controls.addEventListener('start', () => this.tumbling(true));
    this.controls.addEventListener('end', () => this.tumbling(false));
    this.scene.add(new THREE.HemisphereLight(0xdde6ff, 0x3a3530, 1.6));
    const head = new THREE.DirectionalLight(0xffffff, 1.4);
    head.position.set(0.3, 0.5, 1);
    this.camera.add(head);
    this.scene.add(this.camera);
    this.grid = new THREE.GridHelper(20, 20, 0x555b66, 0x3a3f48);
    this.scene.add(this.grid, this.content);
    new ResizeObserver(() => this.resize()).observe(host);
    this.resize();
    const loop = () => {
      if (this.needsRender) {
        this.needsRender = false;
        this.renderer.render(this.scene, this.camera);
      }
      requestAnimationFrame(loop);
    };
    requestAnimationFrame(loop);
  }

  private tumbling(on: boolean) {
    for (const { full, light } of this.tumbleSwaps) {
      full.visible = !on;
      light.visible = on;
    }
    this.needsRender = true;
  }

  private resize() {
    const { clientWidth: w, clientHeight: h } = this.host;
    if (!w || !h) return;
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.needsRender = true;
  }

  /** Replaces what is drawn; resolves once a frame with it has been rendered. */
  show(g: DecodedGeometry, received: number, frameIt: boolean): Promise<Drawn> {
    this.last = g;
    this.rebuild();
    const bounds = g.bounds ? new THREE.Box3(new THREE.Vector3(...g.bounds[0]), new THREE.Vector3(...g.bounds[1])) : null;
    const first = !this.bounds;
    this.bounds = bounds;
    if (bounds && (first || frameIt)) this.frame();
    this.renderer.render(this.scene, this.camera);
    this.needsRender = false;
    return new Promise((resolve) =>
      requestAnimationFrame(() => {
        const now = performance.now();
        this.drawn = { ...this.drawn!, drawMs: now - received, drawnAt: now };
        resolve(this.drawn);
      }),
    );
  }

  clear() {
    this.last = null;
    this.rebuild();
  }

  /**
   * A material by its settings, made once and kept: a disposed material
   * releases its shader program, and compiling it again for every frame of
   * playback cost over 100 ms a frame under a software GL.
   */
  private material<T extends THREE.Material>(key: string, make: () => T): T {
    let m = this.materials.get(key);
    if (!m) {
      m = make();
      this.materials.set(key, m);
    }
    return m as T;
  }

  /** Re-creates the scene's objects from the last geometry (after a display toggle too); materials are reused. */
  rebuild() {
    for (const o of [...this.content.children]) {
      this.content.remove(o);
      o.traverse((x) => (x as THREE.Mesh).geometry?.dispose());
    }
    this.tumbleSwaps = [];
    const g = this.last;
    const drawn: Drawn = { generation: g?.generation ?? 0, node: g?.node ?? '', triangles: 0, lines: 0, points: 0, instances: 0, instancesAsPoints: false, checksum: 0, drawMs: 0, drawnAt: 0 };
    for (const part of g?.parts ?? []) {
      drawn.checksum = (drawn.checksum * 31 + checksum(part.positions) + (part.instances ? checksum(part.instances) : 0)) >>> 0;
      this.addPart(part, drawn);
    }
    this.drawn = drawn;
    this.needsRender = true;
  }

  private addPart(part: GeometryPart, drawn: Drawn) {
    const tris = (part.cornerTriangles ?? part.triangles ?? []).length / 3;
    const count = part.instances ? part.instances.length / 16 : 1;
    if (part.instances && count * tris > INSTANCE_TRIANGLE_BUDGET) {
      // Too many triangles: one point per instance at its origin.
      const pos = new Float32Array(count * 3);
      for (let i = 0; i < count; i++) pos.set(part.instances.subarray(i * 16 + 12, i * 16 + 15), i * 3);
      const material = () => this.material('instance-points', () => new THREE.PointsMaterial({ color: 0xc8d0dc, size: 2, sizeAttenuation: false }));
      const geo = new THREE.BufferGeometry();
      geo.setAttribute('position', new THREE.BufferAttribute(pos, 3));
      const full = new THREE.Points(geo, material());
      this.content.add(full);
      if (count > TUMBLE_POINTS) {
        const k = Math.ceil(count / TUMBLE_POINTS);
        const few = new Float32Array(Math.ceil(count / k) * 3);
        for (let i = 0, j = 0; i < count; i += k, j++) few.set(pos.subarray(i * 3, i * 3 + 3), j * 3);
        const lightGeo = new THREE.BufferGeometry();
        lightGeo.setAttribute('position', new THREE.BufferAttribute(few, 3));
        const light = new THREE.Points(lightGeo, material());
        light.visible = false;
        this.content.add(light);
        this.tumbleSwaps.push({ full, light });
      }
      drawn.instances += count;
      drawn.points += count;
      drawn.instancesAsPoints = true;
      return;
    }
    const objects: THREE.Object3D[] = [];
    const uniform = part.colorsUniform ? new THREE.Color(...(part.colorsUniform as [number, number, number])) : new THREE.Color(0xb9c2cf);
    if (tris > 0) {
      const geo = new THREE.BufferGeometry();
      let hasNormals = false;
      let hasColors = false;
      if (part.corners) {
        geo.setAttribute('position', new THREE.BufferAttribute(part.corners, 3));
        if (part.cornerTriangles) geo.setIndex(new THREE.BufferAttribute(part.cornerTriangles, 1));
        if (part.cornerNormals) geo.setAttribute('normal', new THREE.BufferAttribute(part.cornerNormals, 3));
        if (part.cornerColors) geo.setAttribute('color', new THREE.BufferAttribute(part.cornerColors, 3));
        hasNormals = !!part.cornerNormals;
        hasColors = !!part.cornerColors;
      } else {
        geo.setAttribute('position', new THREE.BufferAttribute(part.positions, 3));
        geo.setIndex(new THREE.BufferAttribute(part.triangles!, 1));
        if (part.normals) geo.setAttribute('normal', new THREE.BufferAttribute(part.normals, 3));
        if (part.colors) geo.setAttribute('color', new THREE.BufferAttribute(part.colors, 3));
        hasNormals = !!part.normals;
        hasColors = !!part.colors;
      }
      if (hasNormals) repairNormals(geo);
      const flat = this.forceFlat || !hasNormals;
      const color = hasColors ? 0xffffff : uniform.getHex();
      const mat = this.material(`mesh ${color} ${hasColors} ${flat}`, () => new THREE.MeshStandardMaterial({ color, vertexColors: hasColors, flatShading: flat, roughness: 0.6, metalness: 0.05, side: THREE.DoubleSide }));
      objects.push(part.instances ? instanced(geo, mat, part.instances) : new THREE.Mesh(geo, mat));
      if (this.wireframe) {
        const wire = this.material('wire', () => new THREE.MeshBasicMaterial({ color: 0x101418, wireframe: true, transparent: true, opacity: 0.35 }));
        objects.push(part.instances ? instanced(geo, wire, part.instances) : new THREE.Mesh(geo, wire));
      }
      drawn.triangles += tris * count;
    }
    if (part.lines?.length) {
      const geo = new THREE.BufferGeometry();
      geo.setAttribute('position', new THREE.BufferAttribute(part.positions, 3));
      if (part.colors) geo.setAttribute('color', new THREE.BufferAttribute(part.colors, 3));
      geo.setIndex(new THREE.BufferAttribute(part.lines, 1));
      const colored = !!part.colors;
      objects.push(new THREE.LineSegments(geo, this.material(`lines ${colored}`, () => new THREE.LineBasicMaterial({ color: colored ? 0xffffff : 0xe0e6ef, vertexColors: colored }))));
      drawn.lines += (part.lines.length / 2) * count;
    }
    if (part.points?.length) {
      const geo = new THREE.BufferGeometry();
      geo.setAttribute('position', new THREE.BufferAttribute(part.positions, 3));
      if (part.colors) geo.setAttribute('color', new THREE.BufferAttribute(part.colors, 3));
      geo.setIndex(new THREE.BufferAttribute(part.points, 1));
      const colored = !!part.colors;
      objects.push(new THREE.Points(geo, this.material(`points ${colored}`, () => new THREE.PointsMaterial({ color: colored ? 0xffffff : 0xf2f5f8, vertexColors: colored, size: 3, sizeAttenuation: false }))));
      drawn.points += part.points.length * count;
    }
    if (part.instances) drawn.instances += count;
    this.content.add(...objects);
  }

  /** Frames the whole result (or the selected points when `selected`). */
  frame(selected = false) {
    const box = (selected && this.selection) || this.bounds;
    if (!box) return;
    const size = box.getSize(new THREE.Vector3()).length() || 1;
    const center = box.getCenter(new THREE.Vector3());
    const dir = this.camera.position.clone().sub(this.controls.target).normalize();
    if (!Number.isFinite(dir.x) || dir.lengthSq() === 0) dir.set(0.5, 0.4, 0.8).normalize();
    const dist = size / (2 * Math.tan((this.camera.fov * Math.PI) / 360)) + size * 0.2;
    this.controls.target.copy(center);
    this.camera.position.copy(center.clone().add(dir.multiplyScalar(dist)));
    this.camera.near = Math.max(1e-4, dist / 1000);
    this.camera.far = dist * 100;
    this.camera.updateProjectionMatrix();
    this.controls.update();
    this.grid.scale.setScalar(Math.max(0.1, 10 ** Math.round(Math.log10(size / 4))));
    this.needsRender = true;
  }

  /** Points picked in the spreadsheet, framed by `F`. */
  select(points: [number, number, number][]) {
    if (!points.length) {
      this.selection = null;
      return;
    }
    const b = new THREE.Box3();
    for (const p of points) b.expandByPoint(new THREE.Vector3(...p));
    b.expandByScalar((this.bounds?.getSize(new THREE.Vector3()).length() ?? 1) * 0.02);
    this.selection = b;
  }
}

/**
 * Zero normals (points merged from geometry without `N` get the default) are
 * replaced by normals computed from the triangles; the others are kept.
 */
export function repairNormals(geo: THREE.BufferGeometry) {
  const n = geo.getAttribute('normal') as THREE.BufferAttribute;
  const zero: number[] = [];
  for (let i = 0; i < n.count; i++) if (n.getX(i) === 0 && n.getY(i) === 0 && n.getZ(i) === 0) zero.push(i);
  if (!zero.length) return;
  const kept = n.clone();
  geo.computeVertexNormals();
  const computed = geo.getAttribute('normal') as THREE.BufferAttribute;
  for (const i of zero) kept.setXYZ(i, computed.getX(i), computed.getY(i), computed.getZ(i));
  geo.setAttribute('normal', kept);
}

function instanced(geo: THREE.BufferGeometry, mat: THREE.Material, matrices: Float32Array): THREE.InstancedMesh {
  const count = matrices.length / 16;
  const mesh = new THREE.InstancedMesh(geo, mat, count);
  mesh.instanceMatrix = new THREE.InstancedBufferAttribute(matrices, 16);
  mesh.frustumCulled = false;
  return mesh;
}
