//! A value of one lane as the library's lane functions see it (an int,
//! float slots, a string or an array), the bytes it holds on the heap, and
//! the conversion from an attribute's element.

use geode_geo::{AttribClass, AttribData, Geometry};

/// A value of one lane, as the per-lane library reads and writes it.
#[derive(Clone, Debug, PartialEq)]
pub enum Val {
    I(i32),
    /// Float slots (1, 2, 3, 4, 9 or 16 used).
    F([f32; 16], u8),
    S(String),
    AF(Vec<f32>, u8),
    AI(Vec<i32>),
    AS(Vec<String>),
}

impl Val {
    pub fn float(x: f32) -> Val {
        Val::vec(&[x])
    }

    pub fn vec(xs: &[f32]) -> Val {
        let mut a = [0.0; 16];
        a[..xs.len()].copy_from_slice(xs);
        Val::F(a, xs.len() as u8)
    }

    pub fn floats(&self) -> &[f32] {
        match self {
            Val::F(a, n) => &a[..*n as usize],
            _ => &[],
        }
    }

    pub fn f(&self) -> f32 {
        match self {
            Val::I(i) => *i as f32,
            Val::F(a, _) => a[0],
            _ => 0.0,
        }
    }

    pub fn i(&self) -> i32 {
        match self {
            Val::I(i) => *i,
            Val::F(a, _) => a[0] as i32,
            _ => 0,
        }
    }

    pub fn s(&self) -> &str {
        match self {
            Val::S(s) => s,
            _ => "",
        }
    }

    pub fn v3(&self) -> [f32; 3] {
        let f = self.floats();
        [
            f.first().copied().unwrap_or(0.0),
            f.get(1).copied().unwrap_or(0.0),
            f.get(2).copied().unwrap_or(0.0),
        ]
    }
}

/// Bytes a value holds on the heap, for the memory budget.
pub trait HeapBytes {
    fn heap_bytes(&self) -> u64;
}

impl HeapBytes for String {
    fn heap_bytes(&self) -> u64 {
        self.capacity() as u64
    }
}

impl HeapBytes for Vec<f32> {
    fn heap_bytes(&self) -> u64 {
        (self.capacity() * 4) as u64
    }
}

impl HeapBytes for Vec<i32> {
    fn heap_bytes(&self) -> u64 {
        (self.capacity() * 4) as u64
    }
}

/// A string array: its slots and every string's characters.
impl HeapBytes for Vec<String> {
    fn heap_bytes(&self) -> u64 {
        let slots = std::mem::size_of_val(self.as_slice()) as u64;
        slots + self.iter().map(HeapBytes::heap_bytes).sum::<u64>()
    }
}

impl HeapBytes for Val {
    fn heap_bytes(&self) -> u64 {
        match self {
            Val::I(_) | Val::F(..) => 0,
            Val::S(s) => s.heap_bytes(),
            Val::AF(v, _) => v.heap_bytes(),
            Val::AI(v) => v.heap_bytes(),
            Val::AS(v) => v.heap_bytes(),
        }
    }
}

/// An attribute's value at an element, as a lane value.
pub fn attrib_value(data: &AttribData, i: usize) -> Val {
    match data {
        AttribData::Float(v) => Val::float(v[i]),
        AttribData::Int(v) => Val::I(v[i]),
        AttribData::Vec2(v) => Val::vec(&v[i].to_array()),
        AttribData::Vec3(v) => Val::vec(&v[i].to_array()),
        AttribData::Vec4(v) => Val::vec(&v[i].to_array()),
        AttribData::Quat(v) => Val::vec(&v[i].to_array()),
        AttribData::Mat4(v) => Val::vec(&v[i].to_cols_array()),
        AttribData::String(s) => Val::S(s.get(i).to_string()),
        AttribData::IntArray(v) => Val::AI(v[i].clone()),
        AttribData::FloatArray(v) => Val::AF(v[i].clone(), 1),
        AttribData::Mat3(v) => Val::vec(&v[i].to_cols_array()),
        AttribData::Vec3Array(v) => Val::AF(v[i].iter().flat_map(|p| p.to_array()).collect(), 3),
        AttribData::StringArray(v) => Val::AS(v[i].clone()),
    }
}

/// An attribute's value at element `idx` of class `class`, if it exists.
pub fn read_attrib(g: &Geometry, class: AttribClass, name: &str, idx: i32) -> Option<Val> {
    if class == AttribClass::Point && name == "P" {
        let p = g.positions().get(usize::try_from(idx).ok()?)?;
        return Some(Val::vec(&p.to_array()));
    }
    let a = g.attrib(class, name)?;
    let i = usize::try_from(idx).ok().filter(|&i| i < a.len())?;
    Some(attrib_value(a.data(), i))
}
