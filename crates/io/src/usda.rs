//! USD ASCII (`.usda`) writer: a Mesh for polygons, BasisCurves for polylines, instanceable prims for packed instances.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::io::Write;
use std::path::Path;

use geode_geo::glam::Vec3;
use geode_geo::{ops, AttribClass, Geometry, PrimKind};

use crate::atomic::os_err;
use crate::error::IoError;
use crate::progress::{describe_attrib, report_dropped, Progress};
use crate::usda_primvars::{matrix4, primvar, write_value, Interpolation};

struct Writer<'w> {
    out: &'w mut dyn Write,
    buf: String,
    path: &'w Path,
    /// Prototype name per distinct packed source, in first-use order.
    protos: Vec<(*const Geometry, String, std::sync::Arc<Geometry>)>,
    proto_index: HashMap<*const Geometry, usize>,
    progress: &'w dyn Progress,
    /// Attributes no primvar could carry, reported once at the end.
    dropped: Vec<String>,
}

impl Writer<'_> {
    fn check_cancelled(&self) -> Result<(), IoError> {
        if self.progress.cancelled() {
            return Err(IoError::Cancelled {
                path: self.path.to_owned(),
            });
        }
        Ok(())
    }

    fn flush_if_big(&mut self) -> Result<(), IoError> {
        if self.buf.len() > 1 << 20 {
            self.out
                .write_all(self.buf.as_bytes())
                .map_err(os_err(self.path))?;
            self.buf.clear();
        }
        Ok(())
    }

    fn array<T, I: std::borrow::Borrow<T>>(
        &mut self,
        indent: &str,
        decl: &str,
        items: impl IntoIterator<Item = I>,
        fmt: impl Fn(&mut String, &T),
        meta: &str,
    ) -> Result<(), IoError> {
        let _ = write!(self.buf, "{indent}{decl} = [");
        for (i, it) in items.into_iter().enumerate() {
            if i > 0 {
                self.buf.push_str(", ");
            }
            fmt(&mut self.buf, it.borrow());
            if i % 4096 == 4095 {
                self.check_cancelled()?;
                self.flush_if_big()?;
            }
        }
        self.buf.push(']');
        if !meta.is_empty() {
            let _ = write!(self.buf, " (\n{indent}    {meta}\n{indent})");
        }
        self.buf.push('\n');
        Ok(())
    }

    fn proto_name(&mut self, src: &std::sync::Arc<Geometry>) -> String {
        let key = std::sync::Arc::as_ptr(src);
        if let Some(&i) = self.proto_index.get(&key) {
            return self.protos[i].1.clone();
        }
        let name = format!("proto_{}", self.protos.len());
        self.proto_index.insert(key, self.protos.len());
        self.protos
            .push((key, name.clone(), std::sync::Arc::clone(src)));
        name
    }

    /// Writes the children of an Xform holding `g`: its mesh, curves, and one
    /// instanceable prim per packed primitive.
    fn body(&mut self, g: &Geometry, indent: &str) -> Result<(), IoError> {
        let p = g.positions();
        let polys: Vec<usize> = g.prims_where(|k| k == PrimKind::Polygon);
        if !polys.is_empty() {
            // Streamed, never collected: a mesh of millions of faces is
            // formatted as it is walked, and a cancel is seen within 4096 items.
            let counts = polys.iter().map(|&i| g.prim_vertex_range(i).len() as u32);
            let indices = polys.iter().flat_map(|&i| g.prim_points(i).iter().copied());
            let _ = writeln!(self.buf, "{indent}def Mesh \"mesh\"\n{indent}{{");
            let inner = format!("{indent}    ");
            if let Some(b) = ops::bounds(g) {
                let _ = writeln!(
                    self.buf,
                    "{inner}float3[] extent = [({}, {}, {}), ({}, {}, {})]",
                    b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z
                );
            }
            self.array(
                &inner,
                "int[] faceVertexCounts",
                counts,
                |s, c| {
                    let _ = write!(s, "{c}");
                },
                "",
            )?;
            self.array(
                &inner,
                "int[] faceVertexIndices",
                indices,
                |s, c| {
                    let _ = write!(s, "{c}");
                },
                "",
            )?;
            let v3 = |s: &mut String, v: &Vec3| {
                let _ = write!(s, "({}, {}, {})", v.x, v.y, v.z);
            };
            self.array(&inner, "point3f[] points", p, v3, "")?;
            self.primvars(g, &inner, &polys, false)?;
            let _ = writeln!(
                self.buf,
                "{inner}uniform token subdivisionScheme = \"none\"\n{indent}}}"
            );
        }
        let lines: Vec<usize> = g.prims_where(|k| k == PrimKind::Polyline);
        if !lines.is_empty() {
            let counts: Vec<u32> = lines
                .iter()
                .map(|&i| g.prim_vertex_range(i).len() as u32)
                .collect();
            let pts: Vec<Vec3> = lines
                .iter()
                .flat_map(|&i| g.prim_points(i).iter().map(|&k| p[k as usize]))
                .collect();
            let _ = writeln!(self.buf, "{indent}def BasisCurves \"curves\"\n{indent}{{");
            let inner = format!("{indent}    ");
            let _ = writeln!(self.buf, "{inner}uniform token type = \"linear\"");
            self.array(
                &inner,
                "int[] curveVertexCounts",
                &counts,
                |s, c: &u32| {
                    let _ = write!(s, "{c}");
                },
                "",
            )?;
            self.array(
                &inner,
                "point3f[] points",
                &pts,
                |s, v: &Vec3| {
                    let _ = write!(s, "({}, {}, {})", v.x, v.y, v.z);
                },
                "",
            )?;
            self.primvars(g, &inner, &lines, true)?;
            let _ = writeln!(self.buf, "{inner}float[] widths = [0.01] (\n{inner}    interpolation = \"constant\"\n{inner})\n{indent}}}");
        }
        self.patches(g, indent)?;
        let mut k = 0;
        for prim in 0..g.num_prims() {
            if !matches!(g.prim_kind(prim), PrimKind::Packed(_)) {
                continue;
            }
            let inst = g.packed_instance(prim).expect("packed");
            let world = g.packed_world_transform(prim).expect("packed has a point");
            let proto = self.proto_name(&inst.source);
            let _ = writeln!(
                self.buf,
                "{indent}def Xform \"instance_{k}\" (\n{indent}    instanceable = true\n{indent}    references = </geode_prototypes/{proto}>\n{indent})\n{indent}{{\n{indent}    matrix4d xformOp:transform = {}\n{indent}    uniform token[] xformOpOrder = [\"xformOp:transform\"]\n{indent}}}",
                matrix4(&world)
            );
            k += 1;
            self.flush_if_big()?;
        }
        Ok(())
    }
}

impl Writer<'_> {
    /// Every attribute of `g` as a primvar of the prim holding `prims`
    /// (polygons of a Mesh, or polylines of BasisCurves, whose points are
    /// their vertices). A vertex attribute wins over a point attribute of
    /// the same USD name.
    fn primvars(
        &mut self,
        g: &Geometry,
        indent: &str,
        prims: &[usize],
        curves: bool,
    ) -> Result<(), IoError> {
        let mut taken = std::collections::HashSet::new();
        for class in [
            AttribClass::Vertex,
            AttribClass::Point,
            AttribClass::Primitive,
            AttribClass::Detail,
        ] {
            for (name, a) in g.attribs(class).iter() {
                if class == AttribClass::Point && name == geode_geo::P {
                    continue;
                }
                let pv = primvar(name, a).filter(|pv| taken.insert(pv.property.clone()));
                let Some(pv) = pv else {
                    let entry = describe_attrib(class, name, a.attrib_type());
                    if !self.dropped.contains(&entry) {
                        self.dropped.push(entry);
                    }
                    continue;
                };
                let interp = Interpolation::of(class, curves);
                let meta = format!("interpolation = \"{}\"", interp.token());
                let decl = format!("{}[] {}", pv.usd_type, pv.property);
                let fmt = |s: &mut String, i: &usize| write_value(s, &pv, *i);
                match class {
                    AttribClass::Point if curves => {
                        let pts = prims
                            .iter()
                            .flat_map(|&i| g.prim_points(i).iter().map(|&k| k as usize));
                        self.array(indent, &decl, pts, fmt, &meta)?
                    }
                    AttribClass::Point => {
                        self.array(indent, &decl, 0..g.num_points(), fmt, &meta)?
                    }
                    AttribClass::Vertex => {
                        let corners = prims.iter().flat_map(|&i| g.prim_vertex_range(i));
                        self.array(indent, &decl, corners, fmt, &meta)?
                    }
                    AttribClass::Primitive => {
                        self.array(indent, &decl, prims.iter().copied(), fmt, &meta)?
                    }
                    AttribClass::Detail => {
                        let _ = write!(self.buf, "{indent}{} {} = ", pv.usd_type, pv.property);
                        write_value(&mut self.buf, &pv, 0);
                        let _ = writeln!(self.buf, " (\n{indent}    {meta}\n{indent})");
                    }
                }
            }
        }
        Ok(())
    }
}

impl Writer<'_> {
    /// One NurbsPatch per spline patch. USD follows RenderMan's RiNuPatch:
    /// u varies fastest in `points`, where geode's grids run v fastest.
    fn patches(&mut self, g: &Geometry, indent: &str) -> Result<(), IoError> {
        let p = g.positions();
        let weights = g
            .attrib(AttribClass::Point, geode_geo::WEIGHT)
            .and_then(|a| a.as_f32());
        for (k, prim) in g
            .prims_where(|kind| matches!(kind, PrimKind::Patch(_)))
            .into_iter()
            .enumerate()
        {
            let basis = g.patch_basis(prim).expect("a patch has knots");
            let (nu, nv) = (basis.u.count(), basis.v.count());
            let grid = g.prim_points(prim);
            let order: Vec<u32> = (0..nv)
                .flat_map(|j| (0..nu).map(move |i| grid[i * nv + j]))
                .collect();
            let inner = format!("{indent}    ");
            let _ = writeln!(self.buf, "{indent}def NurbsPatch \"patch_{k}\"\n{indent}{{");
            for (side, b) in [("u", &basis.u), ("v", &basis.v)] {
                let o = b.order as usize;
                let range = (b.knots[o - 1], b.knots[b.knots.len() - o]);
                let _ = writeln!(
                    self.buf,
                    "{inner}int {side}VertexCount = {}\n{inner}int {side}Order = {o}\n{inner}uniform token {side}Form = \"open\"\n{inner}double2 {side}Range = ({}, {})",
                    b.count(),
                    range.0,
                    range.1
                );
                self.array(
                    &inner,
                    &format!("double[] {side}Knots"),
                    &b.knots,
                    |s, x: &f64| {
                        let _ = write!(s, "{x}");
                    },
                    "",
                )?;
            }
            self.array(
                &inner,
                "point3f[] points",
                &order,
                |s, i: &u32| {
                    let v = p[*i as usize];
                    let _ = write!(s, "({}, {}, {})", v.x, v.y, v.z);
                },
                "",
            )?;
            if let Some(w) = weights {
                self.array(
                    &inner,
                    "double[] pointWeights",
                    &order,
                    |s, i: &u32| {
                        let _ = write!(s, "{}", w[*i as usize]);
                    },
                    "",
                )?;
            }
            let _ = writeln!(self.buf, "{indent}}}");
            self.flush_if_big()?;
        }
        Ok(())
    }
}

/// Writes a `.usda` layer: an Xform `/geode` holding a Mesh (polygons, with
/// normals, displayColor and st primvars), BasisCurves (polylines) and one
/// instanceable Xform per packed instance referencing a prototype under the
/// abstract class `/geode_prototypes`, so instances share their prototype.
pub fn write_usda(
    g: &Geometry,
    w: &mut dyn Write,
    path: &Path,
    progress: &dyn Progress,
) -> Result<(), IoError> {
    progress.start("writing USDA", 1);
    let mut wr = Writer {
        out: w,
        buf: String::new(),
        path,
        protos: Vec::new(),
        proto_index: HashMap::new(),
        progress,
        dropped: Vec::new(),
    };
    let _ = writeln!(
        wr.buf,
        "#usda 1.0\n(\n    defaultPrim = \"geode\"\n    doc = \"written by geode {}\"\n    metersPerUnit = 1\n    upAxis = \"Y\"\n)\n\ndef Xform \"geode\"\n{{",
        env!("CARGO_PKG_VERSION")
    );
    wr.body(g, "    ")?;
    wr.buf.push_str("}\n");
    // Prototypes may themselves instance further prototypes: write until none is new.
    let mut written = 0;
    if !wr.protos.is_empty() {
        wr.buf.push_str("\nclass \"geode_prototypes\"\n{\n");
        while written < wr.protos.len() {
            let (_, name, src) = wr.protos[written].clone();
            let _ = writeln!(wr.buf, "    def Xform \"{name}\"\n    {{");
            wr.body(&src, "        ")?;
            wr.buf.push_str("    }\n");
            written += 1;
        }
        wr.buf.push_str("}\n");
    }
    wr.out.write_all(wr.buf.as_bytes()).map_err(os_err(path))?;
    report_dropped(progress, path, "USD", &wr.dropped);
    progress.finish();
    Ok(())
}
