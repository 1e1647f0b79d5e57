//! STL reader (ASCII and binary) and binary STL writer.

use std::io::Write;
use std::path::Path;

use geode_geo::glam::Vec3;
use geode_geo::{ops, AttribClass, Geometry, PrimKind};
use rayon::prelude::*;

use crate::atomic::os_err;
use crate::error::{IoError, ParseError, ParseResult};
use crate::progress::{describe_attrib, Progress, Throttle};
use crate::text::{parse_f32, Lines};

const HEADER: usize = 80;
const RECORD: usize = 50;

/// True when the bytes are laid out exactly as a binary STL.
fn is_binary(bytes: &[u8]) -> bool {
    if bytes.len() < HEADER + 4 {
        return false;
    }
    let n = u32::from_le_bytes(bytes[HEADER..HEADER + 4].try_into().expect("4 bytes")) as u64;
    (HEADER as u64 + 4 + n * RECORD as u64) == bytes.len() as u64
}

/// Parses STL. Binary when the size matches the triangle count, else ASCII
/// when it starts with `solid`; corners at identical positions share a point.
pub fn read_stl(bytes: &[u8], progress: &dyn Progress) -> ParseResult<Geometry> {
    let corners = if is_binary(bytes) {
        read_binary(bytes)?
    } else if bytes.trim_ascii_start().starts_with(b"solid") {
        read_ascii(bytes, progress)?
    } else if bytes.len() < HEADER + 4 {
        return Err(ParseError::byte(
            bytes.len() as u64,
            format!(
                "truncated binary STL: {} bytes, expected at least 84 (header and triangle count)",
                bytes.len()
            ),
        ));
    } else {
        let n = u32::from_le_bytes(bytes[HEADER..HEADER + 4].try_into().expect("4 bytes")) as u64;
        let expected = HEADER as u64 + 4 + n * RECORD as u64;
        let have = (bytes.len() - HEADER - 4) / RECORD;
        return Err(ParseError::byte(
            (HEADER + 4 + have * RECORD) as u64,
            format!(
                "binary STL declares {n} triangles ({expected} bytes) but the file has {} bytes: {}",
                bytes.len(),
                if (bytes.len() as u64) < expected { "truncated" } else { "trailing data" }
            ),
        ));
    };
    weld(corners)
}

fn read_binary(bytes: &[u8]) -> ParseResult<Vec<Vec3>> {
    let body = &bytes[HEADER + 4..];
    let mut corners = vec![Vec3::ZERO; body.len() / RECORD * 3];
    corners
        .par_chunks_mut(3)
        .zip(body.par_chunks(RECORD))
        .for_each(|(out, rec)| {
            for (k, c) in out.iter_mut().enumerate() {
                let f = |i: usize| {
                    let o = 12 + k * 12 + i * 4;
                    f32::from_le_bytes(rec[o..o + 4].try_into().expect("4 bytes"))
                };
                *c = Vec3::new(f(0), f(1), f(2));
            }
        });
    if let Some(i) = corners.iter().position(|c| !c.is_finite()) {
        let tri = i / 3;
        return Err(ParseError::byte(
            (HEADER + 4 + tri * RECORD + 12 + (i % 3) * 12) as u64,
            format!("triangle {tri} has a non-finite vertex"),
        ));
    }
    Ok(corners)
}

fn read_ascii(bytes: &[u8], progress: &dyn Progress) -> ParseResult<Vec<Vec3>> {
    let mut corners = Vec::new();
    let mut in_loop = 0usize;
    let mut seen_solid = false;
    let mut ended = false;
    let mut throttle = Throttle::new(progress, "reading STL", bytes.len() as u64);
    for (line_no, offset, line) in Lines::new(bytes) {
        throttle.tick(offset as u64);
        let line = line.map_err(|m| ParseError::line(line_no, m))?;
        let mut t = line.split_ascii_whitespace();
        let Some(k) = t.next() else { continue };
        let err = |m: String| ParseError::line(line_no, m);
        match k {
            "solid" if !seen_solid => seen_solid = true,
            "facet" | "outer" | "endfacet" if seen_solid && !ended => {}
            "vertex" if seen_solid && !ended => {
                let v: Vec<f32> = t
                    .map(|x| parse_f32(x).ok_or_else(|| err(format!("expected a number, found `{x}`"))))
                    .collect::<Result<_, _>>()?;
                if v.len() != 3 {
                    return Err(err(format!("`vertex` needs 3 numbers, found {}", v.len())));
                }
                corners.push(Vec3::new(v[0], v[1], v[2]));
                in_loop += 1;
            }
            "endloop" => {
                if in_loop != 3 {
                    return Err(err(format!("a facet needs 3 vertices, found {in_loop}")));
                }
                in_loop = 0;
            }
            "endsolid" => ended = true,
            // Several solids may follow each other in one file.
            "solid" if ended => ended = false,
            other => {
                return Err(err(format!(
                    "unexpected `{}` (expected solid, facet, outer loop, vertex, endloop, endfacet or endsolid)",
                    other.chars().take(32).collect::<String>()
                )))
            }
        }
    }
    throttle.finish();
    if in_loop != 0 {
        return Err(ParseError::whole("file ends inside a facet"));
    }
    Ok(corners)
}

/// Shares one point among corners with bit-identical positions.
fn weld(corners: Vec<Vec3>) -> ParseResult<Geometry> {
    let (positions, vertex_points) = crate::weld::weld_positions(&corners);
    let counts = vec![3u32; corners.len() / 3];
    Geometry::from_polygons(positions, vertex_points, &counts)
        .map_err(|e| ParseError::whole(e.to_string()))
}

/// The triangles (as point indices) of every polygon in primitive order:
/// fans for convex polygons, ear clipping for concave ones (the rule of
/// `ops::triangulate`, without building a geometry). `None` when cancelled.
fn facets(g: &Geometry, cancel: &(dyn Fn() -> bool + Sync)) -> Option<Vec<[u32; 3]>> {
    const CHUNK: usize = 1 << 14;
    let p = g.positions();
    let n = g.num_prims();
    let parts: Vec<Option<Vec<[u32; 3]>>> = (0..n.div_ceil(CHUNK))
        .into_par_iter()
        .map(|c| {
            if cancel() {
                return None;
            }
            let mut out = Vec::new();
            let mut local = Vec::new();
            for prim in c * CHUNK..((c + 1) * CHUNK).min(n) {
                if g.prim_kind(prim) != PrimKind::Polygon {
                    continue;
                }
                let pts = g.prim_points(prim);
                local.clear();
                ops::triangulate_polygon(p, pts, &mut local);
                out.extend(local.iter().map(|t| t.map(|k| pts[k as usize])));
            }
            Some(out)
        })
        .collect();
    let parts: Option<Vec<Vec<[u32; 3]>>> = parts.into_iter().collect();
    Some(parts?.concat())
}

/// Writes binary STL: polygons are triangulated, facet normals computed.
/// Polylines are skipped (STL holds only triangles); packed primitives must be
/// unpacked first.
pub fn write_stl(
    g: &Geometry,
    w: &mut dyn Write,
    path: &Path,
    progress: &dyn Progress,
) -> Result<(), IoError> {
    crate::error::refuse_packed(g, path, "STL")?;
    let p = g.positions();
    let tris = facets(g, &|| progress.cancelled()).ok_or_else(|| IoError::Cancelled {
        path: path.to_owned(),
    })?;
    let count = u32::try_from(tris.len()).map_err(|_| IoError::Unsupported {
        path: path.to_owned(),
        message: "more than 4294967295 triangles".into(),
    })?;
    let e = os_err(path);
    let mut header = [b' '; HEADER];
    let tag = format!("binary STL written by geode {}", env!("CARGO_PKG_VERSION"));
    header[..tag.len()].copy_from_slice(tag.as_bytes());
    w.write_all(&header).map_err(&e)?;
    w.write_all(&count.to_le_bytes()).map_err(&e)?;
    let mut throttle = Throttle::new(progress, "writing STL", tris.len() as u64);
    const BATCH: usize = 1 << 15;
    let mut buf = vec![0u8; BATCH * RECORD];
    for (bi, batch) in tris.chunks(BATCH).enumerate() {
        throttle.tick((bi * BATCH) as u64);
        buf.par_chunks_mut(RECORD)
            .zip(batch.par_iter())
            .for_each(|(rec, tri)| {
                let [a, b, c] = tri.map(|k| p[k as usize]);
                let n = (b - a).cross(c - a).normalize_or_zero();
                for (k, v) in [n, a, b, c].iter().enumerate() {
                    rec[k * 12..k * 12 + 12].copy_from_slice(bytemuck::bytes_of(&v.to_array()));
                }
                rec[48] = 0;
                rec[49] = 0;
            });
        w.write_all(&buf[..batch.len() * RECORD]).map_err(&e)?;
    }
    // STL holds triangle positions only: every attribute but P, every
    // group and every curve is named (what is lost must never be silent).
    let mut dropped: Vec<String> = AttribClass::ALL
        .into_iter()
        .flat_map(|class| {
            g.attribs(class)
                .iter()
                .filter(move |(name, _)| !(class == AttribClass::Point && *name == geode_geo::P))
                .map(move |(name, a)| describe_attrib(class, name, a.attrib_type()))
        })
        .collect();
    dropped.extend(
        g.point_groups()
            .keys()
            .map(|n| format!("point group `{n}`")),
    );
    dropped.extend(
        g.prim_groups()
            .keys()
            .map(|n| format!("primitive group `{n}`")),
    );
    let lines = g
        .prim_kinds()
        .iter()
        .filter(|k| **k == PrimKind::Polyline)
        .count();
    if lines > 0 {
        dropped.push(format!("{lines} polylines (STL holds triangles only)"));
    }
    crate::progress::report_dropped(progress, path, "STL", &dropped);
    throttle.finish();
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::progress::NoProgress;

    #[test]
    fn ascii_with_shared_points() {
        let text = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n\
                    facet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
        let g = read_stl(text.as_bytes(), &NoProgress).unwrap();
        assert_eq!(g.num_prims(), 2);
        assert_eq!(g.num_points(), 4);
        assert_eq!(g.prim_points(1), &[1, 3, 2]);
    }

    #[test]
    fn truncated_binary_names_the_offset() {
        let mut b = vec![0u8; 84 + 50 * 2];
        b[80] = 3;
        let e = read_stl(&b, &NoProgress).unwrap_err();
        assert_eq!(e.pos, Some(crate::Position::Byte(184)));
        assert_eq!(
            e.message,
            "binary STL declares 3 triangles (234 bytes) but the file has 184 bytes: truncated"
        );
        let e = read_stl(
            b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0\n",
            &NoProgress,
        )
        .unwrap_err();
        assert_eq!(
            (e.pos, e.message.as_str()),
            (
                Some(crate::Position::Line(4)),
                "`vertex` needs 3 numbers, found 2"
            )
        );
    }
}
