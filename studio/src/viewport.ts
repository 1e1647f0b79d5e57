// The 3D viewport (three.js): orbit, pan, zoom, frame all or selected; polygons smooth with N else flat, wireframe overlay, points, polylines, Cd; packed instances as GPU instances, or as points when there are too many triangles to draw.

import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { Labels, normalsOverlay, pointsOverlay, type DisplayOptions } from './overlays';
import { deltaKeys, mergeDelta, polygonEdges, type DecodedGeometry, type GeometryPart } from './protocol';

/** The views Houdini's Space+1..4 choose: perspective, and top, front and right orthographic. */
export type ViewName = 'persp' | 'top' | 'front' | 'right';

/** Where a click landed: the part (bundle entry), what was hit by its index in the drawn arrays, and the point in space. */
export interface ViewportHit {
  entry: string;
  hit: { triangle: number } | { segment: number } | { point: number };
  at: [number, number, number];
}

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
  /** Drawn by updating the buffers of the previous result in place (a delta). */
  delta?: boolean;
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
  private camera: THREE.PerspectiveCamera | THREE.OrthographicCamera;
  private perspective: THREE.PerspectiveCamera;
  private ortho = new THREE.OrthographicCamera(-1, 1, 1, -1, -1e5, 1e5);
  view: ViewName = 'persp';
  private controls: OrbitControls;
  display: DisplayOptions = { points: false, normals: false, pointNumbers: false, primNumbers: false };
  private pointLabels: Labels;
  private primLabels: Labels;
  private primCenters: Float32Array | null = null;
  private marker: THREE.Points;
  /** Called with what a click (a press and release without moving) landed on. */
  onPick: ((hit: ViewportHit | null) => void) | null = null;
  private content = new THREE.Group();
  /** Templated nodes' results by path, drawn as ghosts. */
  private templates = new Map<string, THREE.Object3D>();
  private grid: THREE.GridHelper;
  private bounds: THREE.Box3 | null = null;
  private selection: THREE.Box3 | null = null;
  wireframe = false;
  forceFlat = false;
  /** Multisampling: on, unless the GL is a software rasterizer (SwiftShader, llvmpipe), where it costs more than half of every frame. */
  readonly antialias: boolean;
  drawn: Drawn | null = null;
  private last: DecodedGeometry | null = null;
  private needsRender = true;
  /** Full and decimated versions of large point clouds, swapped while tumbling. */
  private tumbleSwaps: { full: THREE.Object3D; light: THREE.Object3D }[] = [];
  /** The buffer attributes made from each part's arrays, by `part index:key` (a delta updates them in place). */
  private attrs = new Map<string, THREE.BufferAttribute[]>();
  /** Materials by their settings, kept across rebuilds (see `material`). */
  private materials = new Map<string, THREE.Material>();

  constructor(private host: HTMLElement) {
    this.antialias = !softwareGL();
    this.renderer = new THREE.WebGLRenderer({ antialias: this.antialias, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(Math.min(2, window.devicePixelRatio));
    this.renderer.setClearColor(0x2b2f36);
    host.appendChild(this.renderer.domElement);
    this.perspective = new THREE.PerspectiveCamera(45, 1, 0.01, 1e5);
    this.camera = this.perspective;
    this.camera.position.set(4, 4.5, 6);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    // Houdini's mouse: left tumbles, middle pans, right dollies.
    this.controls.mouseButtons = { LEFT: THREE.MOUSE.ROTATE, MIDDLE: THREE.MOUSE.PAN, RIGHT: THREE.MOUSE.DOLLY };
    this.controls.zoomSpeed = 2.5;
    this.pointLabels = new Labels(host, 'point-labels');
    this.primLabels = new Labels(host, 'prim-labels');
    const markerGeo = new THREE.BufferGeometry();
    markerGeo.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3), 3));
    this.marker = new THREE.Points(markerGeo, new THREE.PointsMaterial({ color: 0xffd84a, size: 11, sizeAttenuation: false, depthTest: false }));
    this.marker.visible = false;
    this.marker.renderOrder = 10;
    this.clickWatch();
    this.controls.addEventListener('change', () => (this.needsRender = true));
    this.controls.addEventListener('start', () => this.tumbling(true));
    this.controls.addEventListener('end', () => this.tumbling(false));
    this.scene.add(new THREE.HemisphereLight(0xdde6ff, 0x3a3530, 1.6));
    const head = new THREE.DirectionalLight(0xffffff, 1.4);
    head.position.set(0.3, 0.5, 1);
    this.camera.add(head);
    this.scene.add(this.camera);
    this.grid = new THREE.GridHelper(20, 20, 0x555b66, 0x3a3f48);
    this.scene.add(this.grid, this.content, this.marker);
    new ResizeObserver(() => this.resize()).observe(host);
    this.resize();
    const loop = () => {
      if (this.needsRender) {
        this.needsRender = false;
        this.renderer.render(this.scene, this.camera);
        this.drawLabels();
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
    this.perspective.aspect = w / h;
    this.perspective.updateProjectionMatrix();
    this.fitOrtho();
    this.needsRender = true;
  }

  /** The orthographic frustum at the view's aspect, keeping its height. */
  private fitOrtho() {
    const { clientWidth: w, clientHeight: h } = this.host;
    const half = (this.ortho.top - this.ortho.bottom) / 2 || 1;
    const aspect = w && h ? w / h : 1;
    this.ortho.left = -half * aspect;
    this.ortho.right = half * aspect;
    this.ortho.updateProjectionMatrix();
  }

  /** Switches between perspective and the orthographic top, front and right views (Space+1..4). */
  setView(view: ViewName) {
    this.view = view;
    const target = this.controls.target.clone();
    const dist = Math.max(1e-3, this.camera.position.distanceTo(target));
    if (view === 'persp') {
      this.perspective.position.copy(target.clone().add(new THREE.Vector3(0.5, 0.45, 0.75).normalize().multiplyScalar(dist)));
      this.camera = this.perspective;
      this.controls.enableRotate = true;
    } else {
      const dir = { top: new THREE.Vector3(0, 1, 0), front: new THREE.Vector3(0, 0, 1), right: new THREE.Vector3(1, 0, 0) }[view];
      this.ortho.position.copy(target.clone().add(dir.multiplyScalar(dist)));
      this.ortho.up.set(0, view === 'top' ? 0 : 1, view === 'top' ? -1 : 0);
      const size = this.bounds?.getSize(new THREE.Vector3()).length() ?? dist;
      this.ortho.top = size * 0.6;
      this.ortho.bottom = -size * 0.6;
      this.ortho.zoom = 1;
      this.fitOrtho();
      this.camera = this.ortho;
      // Ortho views pan and zoom; tumbling would leave the axis.
      this.controls.enableRotate = false;
    }
    // The ground grid lies in the view's plane (Houdini's construction plane per view).
    this.grid.rotation.set(view === 'front' ? Math.PI / 2 : 0, 0, view === 'right' ? Math.PI / 2 : 0);
    this.controls.object = this.camera;
    this.camera.lookAt(target);
    this.controls.update();
    this.needsRender = true;
  }

  /** A press and release within a few pixels is a pick, not a tumble. */
  private clickWatch() {
    const canvas = this.renderer.domElement;
    let down: [number, number] | null = null;
    canvas.addEventListener('pointerdown', (e) => (down = e.button === 0 ? [e.clientX, e.clientY] : null));
    canvas.addEventListener('pointerup', (e) => {
      if (!down || Math.hypot(e.clientX - down[0], e.clientY - down[1]) > 4) return;
      down = null;
      this.onPick?.(this.raycast(e.clientX, e.clientY));
    });
  }

  /** What lies under a page position: the nearest drawn triangle, segment or loose point of a pickable part. */
  raycast(cx: number, cy: number): ViewportHit | null {
    const r = this.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2(((cx - r.left) / r.width) * 2 - 1, -((cy - r.top) / r.height) * 2 + 1);
    const ray = new THREE.Raycaster();
    const size = this.bounds?.getSize(new THREE.Vector3()).length() ?? 1;
    ray.params.Points = { threshold: size * 0.01 };
    ray.params.Line = { threshold: size * 0.01 };
    ray.setFromCamera(ndc, this.camera);
    const pickable = this.content.children.filter((o) => o.userData.pick);
    for (const h of ray.intersectObjects(pickable, false)) {
      const { entry, pick } = h.object.userData as { entry: string; pick: 'triangle' | 'segment' | 'point' };
      const at = h.point.toArray() as [number, number, number];
      if (pick === 'triangle' && h.faceIndex != null) return { entry, hit: { triangle: h.faceIndex }, at };
      if (pick === 'segment' && h.index != null) return { entry, hit: { segment: Math.floor(h.index / 2) }, at };
      if (pick === 'point' && h.index != null) return { entry, hit: { point: h.index }, at };
    }
    return null;
  }

  /** Marks a picked point (null clears the mark). */
  mark(at: [number, number, number] | null) {
    this.marker.visible = !!at;
    if (at) {
      const p = this.marker.geometry.getAttribute('position') as THREE.BufferAttribute;
      p.setXYZ(0, ...at);
      p.needsUpdate = true;
    }
    this.needsRender = true;
  }

  /** Primitive centres for the primitive numbers (from the server; null while unknown). */
  setPrimCenters(c: Float32Array | null) {
    this.primCenters = c;
    this.needsRender = true;
  }

  private drawLabels() {
    const { clientWidth: w, clientHeight: h } = this.host;
    const first = this.last?.parts.find((p) => p.positions?.length && !p.instances && !p.reduced);
    this.pointLabels.update(this.display.pointNumbers && first ? first.positions : null, this.camera, w, h);
    this.primLabels.update(this.display.primNumbers ? this.primCenters : null, this.camera, w, h);
  }

  /** How many point and primitive numbers are showing (for tests). */
  labelCounts(): [number, number] {
    return [this.pointLabels.count(), this.primLabels.count()];
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

  /** Draws a templated node's result as a ghost (wireframe, translucent, not pickable), replacing its previous one. */
  showTemplate(g: DecodedGeometry) {
    this.dropTemplate(g.node);
    const group = new THREE.Group();
    const ghost = this.material('template', () => new THREE.MeshBasicMaterial({ color: 0x9aa6b8, wireframe: true, transparent: true, opacity: 0.3, depthWrite: false }));
    const lines = this.material('template-lines', () => new THREE.LineBasicMaterial({ color: 0x9aa6b8, transparent: true, opacity: 0.45 }));
    for (const part of g.parts) {
      if (!part.positions?.length) continue;
      const geo = new THREE.BufferGeometry();
      geo.setAttribute('position', new THREE.BufferAttribute(part.positions, 3));
      if (part.polygons) {
        // Polygon edges, as Houdini draws a template: no triangulation diagonals.
        geo.setIndex(new THREE.BufferAttribute(polygonEdges(part.polygons, part.polygonSizes ?? part.polygonSize ?? 3), 1));
        group.add(new THREE.LineSegments(geo, lines));
      } else if (part.corners && part.cornerTriangles) {
        const c = new THREE.BufferGeometry();
        c.setAttribute('position', new THREE.BufferAttribute(part.corners, 3));
        c.setIndex(new THREE.BufferAttribute(part.cornerTriangles, 1));
        group.add(new THREE.Mesh(c, ghost));
      }
      if (part.lines?.length) {
        const l = new THREE.BufferGeometry();
        l.setAttribute('position', new THREE.BufferAttribute(part.positions, 3));
        l.setIndex(new THREE.BufferAttribute(part.lines, 1));
        group.add(new THREE.LineSegments(l, lines));
      }
    }
    this.templates.set(g.node, group);
    this.scene.add(group);
    this.needsRender = true;
  }

  /** Keeps only the ghosts of `paths` (the nodes that still have the template flag). */
  keepTemplates(paths: Set<string>) {
    for (const node of [...this.templates.keys()]) if (!paths.has(node)) this.dropTemplate(node);
  }

  /** The paths drawn as ghosts (for tests). */
  templateNodes(): string[] {
    return [...this.templates.keys()];
  }

  private dropTemplate(node: string) {
    const old = this.templates.get(node);
    if (!old) return;
    this.scene.remove(old);
    old.traverse((x) => (x as THREE.Mesh).geometry?.dispose());
    this.templates.delete(node);
    this.needsRender = true;
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
    this.attrs.clear();
    const g = this.last;
    const drawn: Drawn = { generation: g?.generation ?? 0, node: g?.node ?? '', triangles: 0, lines: 0, points: 0, instances: 0, instancesAsPoints: false, checksum: 0, drawMs: 0, drawnAt: 0 };
    (g?.parts ?? []).forEach((part, i) => {
      drawn.checksum = (drawn.checksum * 31 + checksum(part.positions) + (part.instances ? checksum(part.instances) : 0)) >>> 0;
      this.partIndex = i;
      this.addPart(part, drawn);
    });
    this.drawn = drawn;
    this.needsRender = true;
  }

  private partIndex = 0;

  /** A buffer attribute over one of the current part's arrays, remembered for deltas. */
  private attr(key: string, array: Float32Array, itemSize: number): THREE.BufferAttribute {
    const a = new THREE.BufferAttribute(array, itemSize);
    const k = `${this.partIndex}:${key}`;
    this.attrs.set(k, [...(this.attrs.get(k) ?? []), a]);
    return a;
  }

  /**
   * Applies a delta (only changed arrays, same topology) to what is drawn:
   * the arrays are copied into the existing buffers, which upload again; no
   * object is rebuilt. Falls back to a rebuild where an array has no buffer
   * of its own (instances, overlays). Null when the delta is not for what is drawn.
   */
  applyDelta(delta: DecodedGeometry, received: number): Promise<Drawn> | null {
    const base = this.last;
    if (!base || delta.deltaOf !== base.generation || delta.node !== base.node || delta.parts.length !== base.parts.length) return null;
    const merged = mergeDelta(base, delta);
    const keys = deltaKeys(delta);
    const inPlace = !this.display.points && !this.display.normals && keys.every((ks, i) => ks.every((k) => this.attrs.has(`${i}:${k}`)));
    if (!inPlace) return this.show(merged, received, false);
    this.last = merged;
    const touched = new Set<THREE.BufferGeometry>();
    keys.forEach((ks, i) => {
      for (const k of ks) {
        const data = (merged.parts[i] as unknown as Record<string, Float32Array>)[k];
        for (const a of this.attrs.get(`${i}:${k}`)!) {
          if (a.array.length !== data.length) return;
          (a.array as Float32Array).set(data);
          a.needsUpdate = true;
        }
      }
    });
    // Bounding volumes follow the new positions (culling, picking); zero normals are filled again.
    const normalsChanged = keys.some((ks) => ks.includes('normals') || ks.includes('cornerNormals'));
    this.content.traverse((o) => {
      const geo = (o as THREE.Mesh).geometry;
      if (geo && !touched.has(geo)) {
        touched.add(geo);
        geo.boundingSphere = null;
        geo.boundingBox = null;
        if (normalsChanged && (o as THREE.Mesh).isMesh && geo.getAttribute('normal')) repairNormals(geo);
      }
    });
    this.bounds = merged.bounds ? new THREE.Box3(new THREE.Vector3(...merged.bounds[0]), new THREE.Vector3(...merged.bounds[1])) : null;
    let sum = 0;
    for (const part of merged.parts) sum = (sum * 31 + checksum(part.positions) + (part.instances ? checksum(part.instances) : 0)) >>> 0;
    this.drawn = { ...this.drawn!, generation: merged.generation, checksum: sum };
    this.renderer.render(this.scene, this.camera);
    this.needsRender = false;
    this.drawLabels();
    return new Promise((resolve) =>
      requestAnimationFrame(() => {
        const now = performance.now();
        this.drawn = { ...this.drawn!, drawMs: now - received, drawnAt: now, delta: true };
        resolve(this.drawn);
      }),
    );
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
        geo.setAttribute('position', this.attr('corners', part.corners, 3));
        if (part.cornerTriangles) geo.setIndex(new THREE.BufferAttribute(part.cornerTriangles, 1));
        if (part.cornerNormals) geo.setAttribute('normal', this.attr('cornerNormals', part.cornerNormals, 3));
        if (part.cornerColors) geo.setAttribute('color', this.attr('cornerColors', part.cornerColors, 3));
        hasNormals = !!part.cornerNormals;
        hasColors = !!part.cornerColors;
      } else {
        geo.setAttribute('position', this.attr('positions', part.positions, 3));
        geo.setIndex(new THREE.BufferAttribute(part.triangles!, 1));
        if (part.normals) geo.setAttribute('normal', this.attr('normals', part.normals, 3));
        if (part.colors) geo.setAttribute('color', this.attr('colors', part.colors, 3));
        hasNormals = !!part.normals;
        hasColors = !!part.colors;
      }
      if (hasNormals) repairNormals(geo);
      const flat = this.forceFlat || !hasNormals;
      const color = hasColors ? 0xffffff : uniform.getHex();
      const mat = this.material(`mesh ${color} ${hasColors} ${flat}`, () => new THREE.MeshStandardMaterial({ color, vertexColors: hasColors, flatShading: flat, roughness: 0.6, metalness: 0.05, side: THREE.DoubleSide }));
      const mesh = part.instances ? instanced(geo, mat, part.instances) : new THREE.Mesh(geo, mat);
      // Picking names elements by the drawn arrays: a reduced or instanced part has none of its own.
      if (!part.instances && !part.reduced) mesh.userData = { pick: 'triangle', entry: part.name };
      objects.push(mesh);
      if (this.wireframe) {
        const wire = this.material('wire', () => new THREE.MeshBasicMaterial({ color: 0x101418, wireframe: true, transparent: true, opacity: 0.35 }));
        objects.push(part.instances ? instanced(geo, wire, part.instances) : new THREE.Mesh(geo, wire));
      }
      drawn.triangles += tris * count;
    }
    if (part.lines?.length) {
      const geo = new THREE.BufferGeometry();
      geo.setAttribute('position', this.attr('positions', part.positions, 3));
      if (part.colors) geo.setAttribute('color', this.attr('colors', part.colors, 3));
      geo.setIndex(new THREE.BufferAttribute(part.lines, 1));
      const colored = !!part.colors;
      const lines = new THREE.LineSegments(geo, this.material(`lines ${colored}`, () => new THREE.LineBasicMaterial({ color: colored ? 0xffffff : 0xe0e6ef, vertexColors: colored })));
      if (!part.instances) lines.userData = { pick: 'segment', entry: part.name };
      objects.push(lines);
      drawn.lines += (part.lines.length / 2) * count;
    }
    if (part.points?.length) {
      const geo = new THREE.BufferGeometry();
      geo.setAttribute('position', this.attr('positions', part.positions, 3));
      if (part.colors) geo.setAttribute('color', this.attr('colors', part.colors, 3));
      geo.setIndex(new THREE.BufferAttribute(part.points, 1));
      const colored = !!part.colors;
      const dots = new THREE.Points(geo, this.material(`points ${colored}`, () => new THREE.PointsMaterial({ color: colored ? 0xffffff : 0xf2f5f8, vertexColors: colored, size: 3, sizeAttenuation: false })));
      if (!part.instances && !part.reduced) dots.userData = { pick: 'point', entry: part.name };
      objects.push(dots);
      drawn.points += part.points.length * count;
    }
    if (part.instances) drawn.instances += count;
    if (!part.instances) this.addOverlays(part, objects);
    this.content.add(...objects);
  }

  /** Points and normals over a part, as the display options ask. */
  private addOverlays(part: GeometryPart, objects: THREE.Object3D[]) {
    if (this.display.points) {
      const dots = pointsOverlay(part, this.material('overlay-points', () => new THREE.PointsMaterial({ color: 0xf5d142, size: 4, sizeAttenuation: false })));
      if (dots) objects.push(dots);
    }
    if (this.display.normals) {
      const size = this.last?.bounds ? new THREE.Vector3(...this.last.bounds[1]).distanceTo(new THREE.Vector3(...this.last.bounds[0])) : 1;
      const lines = normalsOverlay(part, size * 0.03, this.material('overlay-normals', () => new THREE.LineBasicMaterial({ color: 0x5aa8ff })));
      if (lines) objects.push(lines);
    }
  }

  /** Frames the whole result (or the selected points when `selected`). */
  frame(selected = false) {
    const box = (selected && this.selection) || this.bounds;
    if (!box) return;
    const size = box.getSize(new THREE.Vector3()).length() || 1;
    const center = box.getCenter(new THREE.Vector3());
    const dir = this.camera.position.clone().sub(this.controls.target).normalize();
    if (!Number.isFinite(dir.x) || dir.lengthSq() === 0) dir.set(0.5, 0.4, 0.8).normalize();
    const dist = size / (2 * Math.tan((this.perspective.fov * Math.PI) / 360)) + size * 0.2;
    if (this.camera === this.ortho) {
      this.ortho.top = size * 0.6;
      this.ortho.bottom = -size * 0.6;
      this.ortho.zoom = 1;
      this.fitOrtho();
    }
    this.controls.target.copy(center);
    this.camera.position.copy(center.clone().add(dir.multiplyScalar(dist)));
    if (this.camera === this.perspective) {
      this.perspective.near = Math.max(1e-4, dist / 1000);
      this.perspective.far = dist * 100;
    }
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
 * Whether WebGL runs on a software rasterizer (no GPU: SwiftShader,
 * llvmpipe). Measured on the chain's cached playback under SwiftShader:
 * 6.9 fps with 4x multisampling, 16.4 without.
 */
export function softwareGL(): boolean {
  try {
    const gl = document.createElement('canvas').getContext('webgl2') ?? document.createElement('canvas').getContext('webgl');
    if (!gl) return false;
    const info = gl.getExtension('WEBGL_debug_renderer_info');
    const name = String(gl.getParameter(info ? info.UNMASKED_RENDERER_WEBGL : gl.RENDERER));
    gl.getExtension('WEBGL_lose_context')?.loseContext();
    return /swiftshader|llvmpipe|softpipe|software/i.test(name);
  } catch {
    return false;
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
  // computeVertexNormals writes into this same attribute (a delta updates it later): keep the given normals and put them back.
  const given = Float32Array.from(n.array as Float32Array);
  geo.computeVertexNormals();
  const zeroSet = new Set(zero);
  for (let i = 0; i < n.count; i++) if (!zeroSet.has(i)) n.setXYZ(i, given[i * 3], given[i * 3 + 1], given[i * 3 + 2]);
  n.needsUpdate = true;
}

function instanced(geo: THREE.BufferGeometry, mat: THREE.Material, matrices: Float32Array): THREE.InstancedMesh {
  const count = matrices.length / 16;
  const mesh = new THREE.InstancedMesh(geo, mat, count);
  mesh.instanceMatrix = new THREE.InstancedBufferAttribute(matrices, 16);
  mesh.frustumCulled = false;
  return mesh;
}
