//! A geometry drawn as a small PNG for Jupyter: its polygons flat-shaded with a depth buffer, its polylines and lone points over them, from the three-quarter view that shows the most of it.

use std::sync::atomic::{AtomicBool, Ordering};

use geode_geo::{AttribClass, Geometry, PrimKind};
use glam::{Mat3, Vec3};
use rayon::prelude::*;

const BACKGROUND: [f32; 3] = [0.17, 0.17, 0.17];
const LINE: [f32; 3] = [1.0, 0.8, 0.4];
const POINT: [f32; 3] = [0.62, 0.8, 1.0];
/// Rendered at this many samples a side per pixel, then averaged (antialiasing).
const SUPERSAMPLE: usize = 2;

/// The picture's pixels: `size` x `size` RGB, rows top to bottom.
pub struct Picture {
    pub size: usize,
    pub rgb: Vec<u8>,
}

/// A camera turned `yaw` about Y and then `pitch` about X (degrees; a
/// positive pitch looks down on the geometry, as Houdini's default view).
fn view(yaw: f32, pitch: f32) -> Mat3 {
    Mat3::from_rotation_x(pitch.to_radians()) * Mat3::from_rotation_y(yaw.to_radians())
}

/// Of eight three-quarter views, the one whose projection of (a sample of)
/// the points covers the largest box, so a flat piece is never edge-on.
fn best_view(points: &[Vec3], centre: Vec3) -> Mat3 {
    let step = (points.len() / 2000).max(1);
    let area = |r: &Mat3| {
        let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
        for p in points.iter().step_by(step) {
            let q = *r * (*p - centre);
            lo = lo.min(q);
            hi = hi.max(q);
        }
        (hi.x - lo.x) * (hi.y - lo.y)
    };
    let mut best = view(35.0, 25.0);
    let mut best_area = f32::MIN;
    for pitch in [25.0, 60.0] {
        for yaw in [35.0, 125.0, 215.0, 305.0] {
            let r = view(yaw, pitch);
            let a = area(&r);
            if a > best_area {
                best = r;
                best_area = a;
            }
        }
    }
    best
}

/// A canvas with a depth buffer, in supersampled pixels.
struct Canvas {
    side: usize,
    color: Vec<[f32; 3]>,
    depth: Vec<f32>,
}

impl Canvas {
    fn new(side: usize) -> Canvas {
        Canvas {
            side,
            color: vec![BACKGROUND; side * side],
            depth: vec![f32::MIN; side * side],
        }
    }

    /// Fills a triangle (screen x, y and depth; larger depth is nearer).
    fn triangle(&mut self, a: Vec3, b: Vec3, c: Vec3, color: [f32; 3]) {
        let area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
        if area.abs() < 1e-12 {
            return;
        }
        let max = (self.side - 1) as f32;
        let x0 = a.x.min(b.x).min(c.x).floor().clamp(0.0, max) as usize;
        let x1 = a.x.max(b.x).max(c.x).ceil().clamp(0.0, max) as usize;
        let y0 = a.y.min(b.y).min(c.y).floor().clamp(0.0, max) as usize;
        let y1 = a.y.max(b.y).max(c.y).ceil().clamp(0.0, max) as usize;
        for y in y0..=y1 {
            for x in x0..=x1 {
                let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
                let w0 = ((b.x - px) * (c.y - py) - (b.y - py) * (c.x - px)) / area;
                let w1 = ((c.x - px) * (a.y - py) - (c.y - py) * (a.x - px)) / area;
                let w2 = 1.0 - w0 - w1;
                if w0 < 0.0 || w1 < 0.0 || w2 < 0.0 {
                    continue;
                }
                let z = w0 * a.z + w1 * b.z + w2 * c.z;
                let i = y * self.side + x;
                if z > self.depth[i] {
                    self.depth[i] = z;
                    self.color[i] = color;
                }
            }
        }
    }

    /// A line over everything (no depth test), one sample wide per step.
    fn line(&mut self, a: Vec3, b: Vec3, color: [f32; 3]) {
        let steps = (b - a).truncate().length().ceil().max(1.0) as usize;
        for k in 0..=steps {
            let p = a.lerp(b, k as f32 / steps as f32);
            self.dot(p, color, SUPERSAMPLE / 2);
        }
    }

    fn dot(&mut self, p: Vec3, color: [f32; 3], radius: usize) {
        let (cx, cy) = (p.x as isize, p.y as isize);
        let r = radius as isize;
        for y in cy - r..=cy + r {
            for x in cx - r..=cx + r {
                if x >= 0 && y >= 0 && (x as usize) < self.side && (y as usize) < self.side {
                    self.color[y as usize * self.side + x as usize] = color;
                }
            }
        }
    }

    /// `self` with `later` drawn under it: each sample the nearer of the
    /// two, `self`'s on a tie (it holds the earlier primitives).
    fn under(mut self, later: Canvas) -> Canvas {
        for i in 0..self.depth.len() {
            if later.depth[i] > self.depth[i] {
                self.depth[i] = later.depth[i];
                self.color[i] = later.color[i];
            }
        }
        self
    }

    /// Averages each block of samples into a pixel.
    fn resolve(&self, size: usize) -> Picture {
        let mut rgb = Vec::with_capacity(size * size * 3);
        let n = (SUPERSAMPLE * SUPERSAMPLE) as f32;
        for y in 0..size {
            for x in 0..size {
                let mut sum = [0.0f32; 3];
                for sy in 0..SUPERSAMPLE {
                    for sx in 0..SUPERSAMPLE {
                        let c =
                            self.color[(y * SUPERSAMPLE + sy) * self.side + x * SUPERSAMPLE + sx];
                        for k in 0..3 {
                            sum[k] += c[k];
                        }
                    }
                }
                rgb.extend(sum.map(|s| (s / n * 255.0).round().clamp(0.0, 255.0) as u8));
            }
        }
        Picture { size, rgb }
    }
}

/// Draws `g` in a `size` x `size` picture; None when `cancelled` says to stop.
///
/// The polygons are drawn in parallel, each worker into a canvas of its own
/// over a run of primitives; the canvases merge in run order, nearest first
/// and the earlier primitive winning a tie, so the picture is the same on
/// any thread count.
pub fn draw(g: &Geometry, size: usize, cancelled: &(dyn Fn() -> bool + Sync)) -> Option<Picture> {
    let side = size * SUPERSAMPLE;
    let Some(view) = View::fit(g.positions(), side) else {
        return Some(Canvas::new(side).resolve(size));
    };
    let screen: Vec<Vec3> = g.positions().par_iter().map(|p| view.screen(*p)).collect();
    let stop = AtomicBool::new(false);
    let runs = runs(g.num_prims(), side);
    let canvases: Vec<Canvas> = runs
        .into_par_iter()
        .map(|run| {
            let mut canvas = Canvas::new(side);
            for prim in run {
                if prim % PRIMS_PER_CHECK == 0 && (stop.load(Ordering::Relaxed) || cancelled()) {
                    stop.store(true, Ordering::Relaxed);
                    break;
                }
                if g.prim_kind(prim) == PrimKind::Polygon {
                    shade_polygon(&mut canvas, g, prim, &view, &screen);
                }
            }
            canvas
        })
        .collect();
    let mut canvas = canvases
        .into_iter()
        .reduce(Canvas::under)
        .unwrap_or_else(|| Canvas::new(side));
    if stop.load(Ordering::Relaxed) {
        return None;
    }
    overlay(&mut canvas, g, &screen);
    Some(canvas.resolve(size))
}

/// Primitives drawn between two looks at whether to stop.
const PRIMS_PER_CHECK: usize = 4096;

/// The memory the workers' canvases may take together.
const CANVAS_BYTES: usize = 256 << 20;

/// The primitives cut into one run per worker, as many as the thread pool
/// and `CANVAS_BYTES` allow (each run draws into a canvas of its own).
fn runs(prims: usize, side: usize) -> Vec<std::ops::Range<usize>> {
    let canvas = side * side * (std::mem::size_of::<[f32; 3]>() + std::mem::size_of::<f32>());
    let workers = rayon::current_num_threads()
        .min(CANVAS_BYTES / canvas.max(1))
        .min(prims.div_ceil(PRIMS_PER_CHECK))
        .max(1);
    let len = prims.div_ceil(workers).max(1);
    (0..prims)
        .step_by(len)
        .map(|s| s..(s + len).min(prims))
        .collect()
}

/// The camera fitted to the points: rotation, centre and scale to samples.
struct View {
    rotation: Mat3,
    centre: Vec3,
    scale: f32,
    half: f32,
}

impl View {
    /// The view of [`best_view`] framing the finite points; None without any.
    fn fit(points: &[Vec3], side: usize) -> Option<View> {
        let finite: Vec<Vec3> = points.iter().copied().filter(|p| p.is_finite()).collect();
        if finite.is_empty() {
            return None;
        }
        let (lo, hi) = finite.iter().fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let centre = (lo + hi) * 0.5;
        let rotation = best_view(&finite, centre);
        let extent = finite
            .iter()
            .step_by((finite.len() / 4000).max(1))
            .map(|p| {
                let q = rotation * (*p - centre);
                q.x.abs().max(q.y.abs())
            })
            .fold(0.0f32, f32::max)
            .max((hi - lo).length() * 0.25)
            .max(1e-9);
        Some(View {
            rotation,
            centre,
            scale: 0.45 * side as f32 / extent,
            half: side as f32 * 0.5,
        })
    }

    /// A point in samples (x right, y down) with its depth (larger is nearer).
    fn screen(&self, p: Vec3) -> Vec3 {
        let q = self.rotation * (p - self.centre);
        Vec3::new(
            self.half + q.x * self.scale,
            self.half - q.y * self.scale,
            q.z,
        )
    }
}

/// One polygon's triangles, flat-shaded by their facing and coloured by
/// `Cd` as Houdini's viewport takes it (the primitive's, else its points').
fn shade_polygon(canvas: &mut Canvas, g: &Geometry, prim: usize, view: &View, screen: &[Vec3]) {
    let light = Vec3::new(0.3, 0.5, 0.8).normalize();
    let prim_cd = g
        .attrib(AttribClass::Primitive, "Cd")
        .and_then(|a| a.as_vec3());
    let point_cd = g.attrib(AttribClass::Point, "Cd").and_then(|a| a.as_vec3());
    let points = g.positions();
    let pts = g.prim_points(prim);
    let mut corners = Vec::with_capacity(pts.len().saturating_sub(2));
    geode_geo::ops::triangulate_polygon(points, pts, &mut corners);
    for t in &corners {
        let ids = t.map(|k| pts[k as usize] as usize);
        let [a, b, c] = ids.map(|i| points[i]);
        let n = (view.rotation * (b - a).cross(c - a)).normalize_or_zero();
        let shade = 0.35 + 0.65 * n.dot(light).abs();
        let base = match (prim_cd, point_cd) {
            (Some(cd), _) => cd[prim],
            (None, Some(cd)) => (cd[ids[0]] + cd[ids[1]] + cd[ids[2]]) / 3.0,
            _ => Vec3::new(0.9, 0.9, 1.0),
        };
        let color = (base.clamp(Vec3::ZERO, Vec3::ONE) * shade).to_array();
        canvas.triangle(screen[ids[0]], screen[ids[1]], screen[ids[2]], color);
    }
}

/// Polylines, packed instances and patches (as their first point) over the
/// shaded polygons; a geometry of points alone as its points.
fn overlay(canvas: &mut Canvas, g: &Geometry, screen: &[Vec3]) {
    let mut any = false;
    for prim in 0..g.num_prims() {
        let pts = g.prim_points(prim);
        match g.prim_kind(prim) {
            PrimKind::Polygon => {}
            PrimKind::Polyline => {
                for w in pts.windows(2) {
                    canvas.line(screen[w[0] as usize], screen[w[1] as usize], LINE);
                }
            }
            PrimKind::Packed(_) | PrimKind::Patch(_) => {
                canvas.dot(screen[pts[0] as usize], POINT, SUPERSAMPLE);
            }
        }
        any = true;
    }
    if !any {
        let finite: Vec<&Vec3> = screen.iter().filter(|p| p.is_finite()).collect();
        for p in finite.iter().step_by((finite.len() / 200_000).max(1)) {
            canvas.dot(**p, POINT, SUPERSAMPLE / 2);
        }
    }
}

/// The picture as PNG bytes.
pub fn png(picture: &Picture) -> Result<Vec<u8>, png::EncodingError> {
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, picture.size as u32, picture.size as u32);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut w = enc.write_header()?;
        w.write_image_data(&picture.rgb)?;
    }
    Ok(out)
}
