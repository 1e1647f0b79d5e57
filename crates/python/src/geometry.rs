//! `geode.Geometry` (native half): a cooked geometry, its columns as read-only numpy views that share its memory, and new geometries made from arrays.

use std::path::PathBuf;
use std::sync::Arc;

use geode_geo::{
    AttribClass, AttribData, AttribType, Attribute, Geometry, Group, PrimKind, TypeInfo,
};
use glam::Vec3;
use numpy::ndarray::{ArrayViewD, IxDyn};
use numpy::{
    Element, PyArray1, PyArrayDyn, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2,
    PyReadonlyArrayDyn, PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::errors::{file_error, invalid, not_found, read_error, refused_error};

/// A geometry, immutable: every change makes a new one (`with_attrib`),
/// so the arrays handed out stay valid and unchanged while they live.
#[pyclass(frozen, name = "Geometry", module = "geode._geode", subclass)]
pub struct PyGeometry {
    pub geo: Arc<Geometry>,
}

impl PyGeometry {
    pub fn new(geo: Arc<Geometry>) -> PyGeometry {
        PyGeometry { geo }
    }
}

pub fn class_of(name: &str) -> PyResult<AttribClass> {
    Ok(match name {
        "point" | "points" => AttribClass::Point,
        "vertex" | "vertices" => AttribClass::Vertex,
        "prim" | "prims" | "primitive" | "primitives" => AttribClass::Primitive,
        "detail" | "global" => AttribClass::Detail,
        _ => {
            return Err(invalid(format!(
                "`{name}` is not an attribute class (point, vertex, prim, detail)"
            )))
        }
    })
}

fn type_of(name: &str) -> PyResult<AttribType> {
    by_name(&AttribType::ALL, name, "an attribute type")
}

/// The one of `all` whose name (its `Display`) is `name`, or an error
/// listing them.
fn by_name<T: Copy + std::fmt::Display>(all: &[T], name: &str, what: &str) -> PyResult<T> {
    all.iter()
        .copied()
        .find(|t| t.to_string() == name)
        .ok_or_else(|| {
            let known: Vec<String> = all.iter().map(|t| t.to_string()).collect();
            invalid(format!("`{name}` is not {what} ({})", known.join(", ")))
        })
}

/// A read-only numpy array over `flat` with `shape`, kept alive by `owner`
/// (the Python geometry that holds the column): nothing is copied.
fn view<'py, T: Element>(
    owner: &Bound<'py, PyGeometry>,
    flat: &[T],
    shape: &[usize],
) -> PyResult<Bound<'py, PyAny>> {
    let v = ArrayViewD::from_shape(IxDyn(shape), flat)
        .map_err(|e| invalid(format!("column shape: {e}")))?;
    // SAFETY: `owner` holds the `Arc<Geometry>` whose column `flat` borrows,
    // and a geometry is never written once shared with Python (every change
    // makes a new one), so the memory outlives the array and never changes.
    let arr = unsafe { PyArrayDyn::<T>::borrow_from_array(&v, owner.clone().into_any()) };
    read_only(&arr)?;
    Ok(arr.into_any())
}

fn read_only<T: Element>(arr: &Bound<'_, PyArrayDyn<T>>) -> PyResult<()> {
    let kw = PyDict::new(arr.py());
    kw.set_item("write", false)?;
    arr.call_method("setflags", (), Some(&kw))?;
    Ok(())
}

fn floats<T: bytemuck::Pod>(v: &[T]) -> &[f32] {
    bytemuck::cast_slice(v)
}

/// The column as numpy: numeric columns zero-copy, strings and arrays as
/// Python lists (the Python layer makes object arrays of them).
fn column<'py>(owner: &Bound<'py, PyGeometry>, data: &AttribData) -> PyResult<Bound<'py, PyAny>> {
    let py = owner.py();
    let n = data.len();
    match data {
        AttribData::Float(v) => view(owner, v, &[n]),
        AttribData::Int(v) => view(owner, v, &[n]),
        AttribData::Vec2(v) => view(owner, floats(v), &[n, 2]),
        AttribData::Vec3(v) => view(owner, floats(v), &[n, 3]),
        AttribData::Vec4(v) => view(owner, floats(v), &[n, 4]),
        AttribData::Quat(v) => view(owner, floats(v), &[n, 4]),
        // glam stores columns; read as rows they are Houdini's row-vector
        // matrices (p' = p @ M), the layout `hou` returns.
        AttribData::Mat3(v) => view(owner, floats(v), &[n, 3, 3]),
        AttribData::Mat4(v) => view(owner, floats(v), &[n, 4, 4]),
        AttribData::String(s) => Ok(PyList::new(py, (0..n).map(|i| s.get(i)))?.into_any()),
        AttribData::IntArray(v) => {
            Ok(PyList::new(py, v.iter().map(|a| PyArray1::from_slice(py, a)))?.into_any())
        }
        AttribData::FloatArray(v) => {
            Ok(PyList::new(py, v.iter().map(|a| PyArray1::from_slice(py, a)))?.into_any())
        }
        AttribData::Vec3Array(v) => {
            let items = v
                .iter()
                .map(|a| PyArray1::from_slice(py, floats(a)).reshape([a.len(), 3]))
                .collect::<PyResult<Vec<_>>>()?;
            Ok(PyList::new(py, items)?.into_any())
        }
        AttribData::StringArray(v) => {
            Ok(PyList::new(py, v.iter().map(|a| PyList::new(py, a).ok()))?.into_any())
        }
    }
}

fn kind_name(k: PrimKind) -> &'static str {
    k.name()
}

#[pymethods]
impl PyGeometry {
    /// An empty geometry, or another handle on `share`'s (nothing copied).
    #[new]
    #[pyo3(signature = (share = None))]
    fn py_new(share: Option<&Bound<'_, PyGeometry>>) -> PyGeometry {
        match share {
            Some(g) => PyGeometry::new(g.get().geo.clone()),
            None => PyGeometry::new(Arc::new(Geometry::new())),
        }
    }

    #[getter]
    fn num_points(&self) -> usize {
        self.geo.num_points()
    }
    #[getter]
    fn num_vertices(&self) -> usize {
        self.geo.num_vertices()
    }
    #[getter]
    fn num_prims(&self) -> usize {
        self.geo.num_prims()
    }

    /// The geometry's content hash (32 hex digits): equal geometry, equal hash.
    #[getter]
    fn content_hash(&self) -> String {
        format!("{:032x}", self.geo.content_hash())
    }

    /// Names of the attributes of `class` (point, vertex, prim, detail).
    fn attrib_names(&self, class: &str) -> PyResult<Vec<String>> {
        Ok(self
            .geo
            .attribs(class_of(class)?)
            .names()
            .map(str::to_owned)
            .collect())
    }

    /// `(type, type_info)` of an attribute: `("vector3", "position")`.
    fn attrib_type(&self, class: &str, name: &str) -> PyResult<(String, String)> {
        let a = self.attribute(class, name)?;
        Ok((a.attrib_type().to_string(), a.type_info.to_string()))
    }

    /// An attribute's values: numeric columns as read-only numpy arrays
    /// sharing the geometry's memory; strings and arrays as lists.
    fn attrib<'py>(slf: &Bound<'py, Self>, class: &str, name: &str) -> PyResult<Bound<'py, PyAny>> {
        let a = slf.get().attribute(class, name)?;
        column(slf, a.data())
    }

    /// For each primitive, where its vertices start in `prim_points`, and the end (length prims + 1).
    #[getter]
    fn prim_offsets<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        let g = &slf.get().geo;
        view(slf, g.prim_offsets(), &[g.prim_offsets().len()])
    }

    /// The point of every vertex, primitive after primitive.
    #[getter]
    fn prim_points<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        let g = &slf.get().geo;
        view(slf, g.vertex_points(), &[g.num_vertices()])
    }

    /// Each primitive's kind: polygon, polyline, packed, patch.
    #[getter]
    fn prim_types(&self) -> Vec<&'static str> {
        self.geo
            .prim_kinds()
            .iter()
            .map(|k| kind_name(*k))
            .collect()
    }

    /// Groups of `class` (point or prim) as `{name: bool array}`.
    fn groups<'py>(&self, py: Python<'py>, class: &str) -> PyResult<Bound<'py, PyDict>> {
        let (groups, len) = match class_of(class)? {
            AttribClass::Point => (self.geo.point_groups(), self.geo.num_points()),
            AttribClass::Primitive => (self.geo.prim_groups(), self.geo.num_prims()),
            _ => return Err(invalid("groups are of points or prims")),
        };
        let d = PyDict::new(py);
        for (name, g) in groups {
            let flags: Vec<bool> = (0..len).map(|i| g.contains(i)).collect();
            d.set_item(name, PyArray1::from_vec(py, flags))?;
        }
        Ok(d)
    }

    /// Triangles of every polygon (ear clipping, as geode's triangulate
    /// node), as an (n, 3) array of point indices.
    fn triangles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let g = &self.geo;
        let mut tris: Vec<[u32; 3]> = Vec::new();
        py.detach(|| {
            let mut corners = Vec::new();
            for prim in 0..g.num_prims() {
                if g.prim_kind(prim) == PrimKind::Polygon {
                    let pts = g.prim_points(prim);
                    corners.clear();
                    geode_geo::ops::triangulate_polygon(g.positions(), pts, &mut corners);
                    // Corners index the polygon's own vertices.
                    tris.extend(corners.iter().map(|c| c.map(|k| pts[k as usize])));
                }
            }
        });
        let flat: Vec<u32> = bytemuck::cast_slice(&tris).to_vec();
        Ok(PyArray1::from_vec(py, flat)
            .reshape([tris.len(), 3])?
            .into_any())
    }

    /// A new geometry with attribute `name` of `class` and type `ty` set
    /// from `values`: a contiguous float32 array for float, vector and
    /// matrix types, int32 for int, a list of str for string, a list of
    /// number lists (str lists for string arrays) for the array types.
    /// `type_info` tells transforms how to treat it (see [`type_info`]).
    #[pyo3(signature = (class, name, ty, values, type_info = None))]
    fn with_attrib(
        &self,
        class: &str,
        name: &str,
        ty: &str,
        values: &Bound<'_, PyAny>,
        type_info: Option<&str>,
    ) -> PyResult<PyGeometry> {
        let class = class_of(class)?;
        let ty = type_of(ty)?;
        let expected = self.geo.attribs(class).len();
        let data = match ty {
            AttribType::Int => {
                let ints: PyReadonlyArrayDyn<'_, i32> = values.extract()?;
                AttribData::Int(ints.as_slice()?.to_vec())
            }
            AttribType::String => AttribData::String(string_column(values.extract()?)),
            AttribType::IntArray | AttribType::FloatArray | AttribType::Vec3Array => {
                array_column(ty, values.extract()?)?
            }
            AttribType::StringArray => AttribData::StringArray(values.extract()?),
            _ => {
                let floats: PyReadonlyArrayDyn<'_, f32> = values.extract()?;
                let what = format!("{class} attribute `{name}`");
                float_column(ty, floats.as_slice()?, expected, &what)?
            }
        };
        if data.len() != expected {
            return Err(invalid(format!(
                "{class} attribute `{name}` needs {expected} values, got {}",
                data.len()
            )));
        }
        check_name(name)?;
        let info = self.type_info(class, name, ty, type_info)?;
        let mut g = (*self.geo).clone();
        g.set_attrib(class, name, Attribute::from_data(data, info))
            .map_err(|e| invalid(e.to_string()))?;
        Ok(PyGeometry::new(Arc::new(g)))
    }

    /// A new geometry without attribute `name` of `class`.
    fn without_attrib(&self, class: &str, name: &str) -> PyResult<PyGeometry> {
        let mut g = (*self.geo).clone();
        g.remove_attrib(class_of(class)?, name)
            .map_err(|e| invalid(e.to_string()))?;
        Ok(PyGeometry::new(Arc::new(g)))
    }

    /// A new geometry with group `name` of `class` (point or prim) set from a boolean mask.
    fn with_group(
        &self,
        class: &str,
        name: &str,
        mask: PyReadonlyArray1<'_, bool>,
    ) -> PyResult<PyGeometry> {
        check_name(name)?;
        let mask = mask.as_slice()?;
        let mut g = (*self.geo).clone();
        let group = Group::from_flags(mask.iter().copied());
        let class = class_of(class)?;
        let len = match class {
            AttribClass::Point => g.num_points(),
            AttribClass::Primitive => g.num_prims(),
            _ => return Err(invalid("groups are of points or prims")),
        };
        if mask.len() != len {
            return Err(invalid(format!(
                "group `{name}` needs {len} flags, got {}",
                mask.len()
            )));
        }
        let set = if class == AttribClass::Point {
            g.set_point_group(name, group)
        } else {
            g.set_prim_group(name, group)
        };
        set.map_err(|e| invalid(e.to_string()))?;
        Ok(PyGeometry::new(Arc::new(g)))
    }

    /// Polygons and polylines from arrays: positions (n, 3), every vertex's
    /// point, a vertex count per primitive and whether each is closed.
    #[staticmethod]
    fn from_prims(
        py: Python<'_>,
        points: PyReadonlyArray2<'_, f32>,
        vertex_points: PyReadonlyArray1<'_, u32>,
        counts: PyReadonlyArray1<'_, u32>,
        closed: PyReadonlyArray1<'_, bool>,
    ) -> PyResult<PyGeometry> {
        if points.shape()[1] != 3 {
            return Err(invalid(format!(
                "points must be (n, 3), not {:?}",
                points.shape()
            )));
        }
        let positions: Vec<Vec3> = bytemuck::cast_slice(points.as_slice()?).to_vec();
        let vp = vertex_points.as_slice()?.to_vec();
        let counts = counts.as_slice()?.to_vec();
        let kinds: Vec<PrimKind> = closed
            .as_slice()?
            .iter()
            .map(|&c| {
                if c {
                    PrimKind::Polygon
                } else {
                    PrimKind::Polyline
                }
            })
            .collect();
        let g = py
            .detach(|| Geometry::from_prims(positions, vp, &counts, kinds))
            .map_err(|e| invalid(e.to_string()))?;
        Ok(PyGeometry::new(Arc::new(g)))
    }

    /// Reads a geometry file (any format geode reads).
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<PyGeometry> {
        let from = path.clone();
        let g = crate::cancel::run_interruptibly(py, move |cancel| {
            // Read as the file node reads: the format first, then the bytes,
            // a file bigger than the memory budget refused before it is read.
            let progress = FileProgress::new(cancel);
            let format = geode_io::read_format(&from).map_err(|e| read_error(&from, &e))?;
            let bytes = geode_op::FileAccess::anywhere()
                .read(&from, progress.budget, &|| progress.cancel.is_cancelled())
                .map_err(|e| refused_error(&from, &e))?;
            geode_io::read_bytes(&bytes, format, &from, &progress)
                .map_err(|e| read_error(&from, &e))
        })??;
        Ok(PyGeometry::new(Arc::new(g)))
    }

    /// Writes the geometry atomically; the extension picks the format
    /// (.obj .stl .ply .glb .usda .geo .bgeo). Ctrl-C stops a long write
    /// and leaves nothing behind.
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let geo = self.geo.clone();
        let to = path.clone();
        crate::cancel::run_interruptibly(py, move |cancel| -> Result<(), String> {
            let g = geode_nodes::for_file(&geo, &to).map_err(|e| e.to_string())?;
            let progress = FileProgress::new(cancel);
            geode_io::write_limited(&g, &to, &progress, progress.budget).map_err(|e| e.to_string())
        })?
        .map_err(|e| file_error(&path, e))
    }

    /// The geometry drawn as a `size` x `size` PNG (Jupyter shows it):
    /// polygons flat-shaded with a depth buffer, polylines and points over
    /// them. Ctrl-C stops a long drawing.
    #[pyo3(signature = (size = 320))]
    fn png<'py>(&self, py: Python<'py>, size: usize) -> PyResult<Bound<'py, pyo3::types::PyBytes>> {
        if !(16..=1024).contains(&size) {
            return Err(invalid(format!(
                "a picture is 16 to 1024 pixels a side, not {size}"
            )));
        }
        let geo = self.geo.clone();
        let drawn = crate::cancel::run_interruptibly(py, move |cancel| {
            crate::picture::draw(&geo, size, &|| cancel.is_cancelled())
                .map(|p| crate::picture::png(&p))
        })?;
        match drawn {
            Some(Ok(bytes)) => Ok(pyo3::types::PyBytes::new(py, &bytes)),
            Some(Err(e)) => Err(invalid(format!("PNG encoding: {e}"))),
            None => Err(pyo3::exceptions::PyKeyboardInterrupt::new_err(
                "the drawing was cancelled",
            )),
        }
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<PyGeometry>()
            .is_ok_and(|o| o.get().geo.content_hash() == self.geo.content_hash())
    }

    fn __hash__(&self) -> u64 {
        self.geo.content_hash() as u64
    }
}

impl PyGeometry {
    /// The tag a set attribute gets: the one asked for; else the one the
    /// attribute it replaces had; else Houdini's for its name (`N` a
    /// normal, `Cd` a colour, `orient` a quaternion), where its type can
    /// carry it.
    fn type_info(
        &self,
        class: AttribClass,
        name: &str,
        ty: AttribType,
        asked: Option<&str>,
    ) -> PyResult<TypeInfo> {
        if let Some(asked) = asked {
            let info = by_name(&TypeInfo::ALL, asked, "a type info")?;
            if !carries(ty, info) {
                return Err(invalid(format!("a {ty} attribute cannot be a {info}")));
            }
            return Ok(info);
        }
        if let Some(old) = self.geo.attrib(class, name) {
            if old.attrib_type() == ty {
                return Ok(old.type_info);
            }
        }
        // A quaternion is one whatever its name; others by Houdini's names.
        let by_name = match ty {
            AttribType::Quat => TypeInfo::Quaternion,
            _ => TypeInfo::for_name(name),
        };
        Ok(if carries(ty, by_name) {
            by_name
        } else {
            TypeInfo::None
        })
    }

    fn attribute(&self, class: &str, name: &str) -> PyResult<&Attribute> {
        let class = class_of(class)?;
        self.geo.attrib(class, name).ok_or_else(|| {
            let known: Vec<&str> = self.geo.attribs(class).names().collect();
            not_found(
                "attribute",
                "",
                None,
                format!(
                    "no {class} attribute `{name}` (there are: {})",
                    if known.is_empty() {
                        "none".to_owned()
                    } else {
                        known.join(", ")
                    }
                ),
            )
        })
    }
}

/// Refuses a name Houdini would not take for an attribute or group.
fn check_name(name: &str) -> PyResult<()> {
    if geode_geo::attrib::is_valid_name(name) {
        Ok(())
    } else {
        Err(invalid(format!(
            "`{name}` is not an attribute or group name (letters, digits and _, not starting with a digit)"
        )))
    }
}

/// Whether values of `ty` can carry the tag `info` (what transforms do with it).
fn carries(ty: AttribType, info: TypeInfo) -> bool {
    match info {
        TypeInfo::None | TypeInfo::TexCoord => true,
        TypeInfo::Position | TypeInfo::Vector | TypeInfo::Normal => ty == AttribType::Vec3,
        TypeInfo::Color => matches!(ty, AttribType::Vec3 | AttribType::Vec4),
        TypeInfo::Quaternion => matches!(ty, AttribType::Quat | AttribType::Vec4),
        // What transforms turn: a 4x4 instance transform, not a 3x3.
        TypeInfo::Transform => ty == AttribType::Mat4,
    }
}

/// A float column of `ty` from flat data: `len` elements of `ty`'s width.
fn float_column(ty: AttribType, f: &[f32], len: usize, what: &str) -> PyResult<AttribData> {
    let rows = |width: usize| -> PyResult<&[f32]> {
        if f.len() == width * len {
            Ok(f)
        } else {
            Err(invalid(match width {
                1 => format!("{what} needs {len} values, got {}", f.len()),
                _ => format!(
                    "{what} needs {len} {ty} values ({} numbers), got {} numbers",
                    width * len,
                    f.len()
                ),
            }))
        }
    };
    fn cast<T: bytemuck::Pod>(f: &[f32]) -> Vec<T> {
        bytemuck::cast_slice(f).to_vec()
    }
    Ok(match ty {
        AttribType::Float => AttribData::Float(rows(1)?.to_vec()),
        AttribType::Vec2 => AttribData::Vec2(cast(rows(2)?)),
        AttribType::Vec3 => AttribData::Vec3(cast(rows(3)?)),
        AttribType::Vec4 => AttribData::Vec4(cast(rows(4)?)),
        AttribType::Quat => AttribData::Quat(cast(rows(4)?)),
        AttribType::Mat3 => AttribData::Mat3(cast(rows(9)?)),
        AttribType::Mat4 => AttribData::Mat4(cast(rows(16)?)),
        _ => return Err(invalid(format!("floats cannot make a {ty} attribute"))),
    })
}

/// An int array's element: a whole number int32 holds, never truncated.
fn whole(x: f64) -> PyResult<i32> {
    if x.fract() == 0.0 && (f64::from(i32::MIN)..=f64::from(i32::MAX)).contains(&x) {
        Ok(x as i32)
    } else {
        Err(invalid(format!(
            "an int array holds whole numbers of 32 bits, not {x}"
        )))
    }
}

/// A string column, each distinct string stored once.
fn string_column(values: Vec<String>) -> geode_geo::StringColumn {
    let mut ids = std::collections::HashMap::new();
    let mut col = geode_geo::StringColumn::default();
    for v in values {
        let next = col.table.len() as u32;
        let id = *ids.entry(v.clone()).or_insert_with(|| {
            col.table.push(v);
            next
        });
        col.indices.push(id);
    }
    col
}

/// An array column (int, float or vector3 arrays) from one list per element.
fn array_column(ty: AttribType, a: Vec<Vec<f64>>) -> PyResult<AttribData> {
    Ok(match ty {
        AttribType::IntArray => AttribData::IntArray(
            a.into_iter()
                .map(|v| v.into_iter().map(whole).collect::<PyResult<Vec<i32>>>())
                .collect::<PyResult<_>>()?,
        ),
        AttribType::FloatArray => AttribData::FloatArray(
            a.into_iter()
                .map(|v| v.into_iter().map(|x| x as f32).collect())
                .collect(),
        ),
        AttribType::Vec3Array => AttribData::Vec3Array(
            a.into_iter()
                .map(|v| {
                    if v.len() % 3 != 0 {
                        return Err(invalid("a vector3 array needs 3 numbers per vector"));
                    }
                    Ok(v.chunks(3)
                        .map(|c| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32))
                        .collect())
                })
                .collect::<PyResult<_>>()?,
        ),
        _ => return Err(invalid(format!("lists cannot make a {ty} attribute"))),
    })
}

/// geode-io's progress for Python's reads and writes: Ctrl-C cancels, and
/// `GEODE_MEMORY_MB`'s budget refuses a file too big before it is read.
struct FileProgress {
    cancel: geode_op::CancelToken,
    budget: u64,
}

impl FileProgress {
    fn new(cancel: geode_op::CancelToken) -> FileProgress {
        FileProgress {
            cancel,
            budget: geode_op::budget_from_env(),
        }
    }
}

impl geode_io::Progress for FileProgress {
    fn cancelled(&self) -> bool {
        self.cancel.is_cancelled()
    }
    fn memory_budget(&self) -> u64 {
        self.budget
    }
}
