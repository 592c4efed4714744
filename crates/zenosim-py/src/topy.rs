//! Serde values as Python objects, built directly: what `json.loads(serde_json::to_string(v))`
//! gives (the same keys in the same order, integers as `int`, other numbers as `float`,
//! non-finite numbers as `None` like summary.json's `null`), without the text in between.

use std::fmt;

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use pyo3::IntoPyObjectExt;
use serde::ser::{self, Serialize};

/// `value` as Python objects.
pub fn to_python<'py, T: Serialize + ?Sized>(
    py: Python<'py>,
    value: &T,
) -> PyResult<Bound<'py, PyAny>> {
    value
        .serialize(Builder { py })
        .map_err(|error| error.into_py())
}

/// Why a value could not be built.
#[derive(Debug)]
pub enum Error {
    /// Python refused (out of memory, say).
    Python(PyErr),
    /// A kind of value summary.json never holds.
    Unsupported(&'static str),
    /// Serde's own.
    Custom(String),
}

impl Error {
    fn into_py(self) -> PyErr {
        match self {
            Self::Python(error) => error,
            other => pyo3::exceptions::PyRuntimeError::new_err(other.to_string()),
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Python(error) => error.fmt(f),
            Self::Unsupported(what) => write!(f, "cannot turn {what} into a Python object"),
            Self::Custom(text) => f.write_str(text),
        }
    }
}

impl std::error::Error for Error {}

impl ser::Error for Error {
    fn custom<T: fmt::Display>(msg: T) -> Self {
        Self::Custom(msg.to_string())
    }
}

impl From<PyErr> for Error {
    fn from(error: PyErr) -> Self {
        Self::Python(error)
    }
}

#[derive(Clone, Copy)]
struct Builder<'py> {
    py: Python<'py>,
}

type Built<'py> = Result<Bound<'py, PyAny>, Error>;

impl<'py> Builder<'py> {
    fn object<T: pyo3::IntoPyObject<'py>>(self, value: T) -> Built<'py> {
        Ok(value.into_bound_py_any(self.py)?)
    }
}

/// A list being built.
struct Seq<'py> {
    builder: Builder<'py>,
    items: Vec<Bound<'py, PyAny>>,
}

/// A dict being built, keys in order.
struct Map<'py> {
    builder: Builder<'py>,
    dict: Bound<'py, PyDict>,
    key: Option<Bound<'py, PyAny>>,
}

impl<'py> ser::Serializer for Builder<'py> {
    type Ok = Bound<'py, PyAny>;
    type Error = Error;
    type SerializeSeq = Seq<'py>;
    type SerializeTuple = Seq<'py>;
    type SerializeTupleStruct = Seq<'py>;
    type SerializeTupleVariant = ser::Impossible<Self::Ok, Error>;
    type SerializeMap = Map<'py>;
    type SerializeStruct = Map<'py>;
    type SerializeStructVariant = ser::Impossible<Self::Ok, Error>;

    fn serialize_bool(self, v: bool) -> Built<'py> {
        self.object(v)
    }
    fn serialize_i8(self, v: i8) -> Built<'py> {
        self.object(v)
    }
    fn serialize_i16(self, v: i16) -> Built<'py> {
        self.object(v)
    }
    fn serialize_i32(self, v: i32) -> Built<'py> {
        self.object(v)
    }
    fn serialize_i64(self, v: i64) -> Built<'py> {
        self.object(v)
    }
    fn serialize_u8(self, v: u8) -> Built<'py> {
        self.object(v)
    }
    fn serialize_u16(self, v: u16) -> Built<'py> {
        self.object(v)
    }
    fn serialize_u32(self, v: u32) -> Built<'py> {
        self.object(v)
    }
    fn serialize_u64(self, v: u64) -> Built<'py> {
        self.object(v)
    }
    fn serialize_f32(self, v: f32) -> Built<'py> {
        self.serialize_f64(f64::from(v))
    }
    /// Non-finite numbers are `None`, as serde_json writes them `null`.
    fn serialize_f64(self, v: f64) -> Built<'py> {
        if v.is_finite() {
            self.object(v)
        } else {
            Ok(self.py.None().into_bound(self.py))
        }
    }
    fn serialize_char(self, v: char) -> Built<'py> {
        self.object(v.to_string())
    }
    fn serialize_str(self, v: &str) -> Built<'py> {
        self.object(v)
    }
    fn serialize_bytes(self, _: &[u8]) -> Built<'py> {
        Err(Error::Unsupported("bytes"))
    }
    fn serialize_none(self) -> Built<'py> {
        Ok(self.py.None().into_bound(self.py))
    }
    fn serialize_some<T: Serialize + ?Sized>(self, value: &T) -> Built<'py> {
        value.serialize(self)
    }
    fn serialize_unit(self) -> Built<'py> {
        self.serialize_none()
    }
    fn serialize_unit_struct(self, _: &'static str) -> Built<'py> {
        self.serialize_none()
    }
    fn serialize_unit_variant(self, _: &'static str, _: u32, variant: &'static str) -> Built<'py> {
        self.serialize_str(variant)
    }
    fn serialize_newtype_struct<T: Serialize + ?Sized>(
        self,
        _: &'static str,
        value: &T,
    ) -> Built<'py> {
        value.serialize(self)
    }
    fn serialize_newtype_variant<T: Serialize + ?Sized>(
        self,
        _: &'static str,
        _: u32,
        variant: &'static str,
        value: &T,
    ) -> Built<'py> {
        let dict = PyDict::new(self.py);
        dict.set_item(variant, value.serialize(self)?)?;
        Ok(dict.into_any())
    }
    fn serialize_seq(self, len: Option<usize>) -> Result<Seq<'py>, Error> {
        Ok(Seq {
            builder: self,
            items: Vec::with_capacity(len.unwrap_or(0)),
        })
    }
    fn serialize_tuple(self, len: usize) -> Result<Seq<'py>, Error> {
        self.serialize_seq(Some(len))
    }
    fn serialize_tuple_struct(self, _: &'static str, len: usize) -> Result<Seq<'py>, Error> {
        self.serialize_seq(Some(len))
    }
    fn serialize_tuple_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeTupleVariant, Error> {
        Err(Error::Unsupported("a tuple variant"))
    }
    fn serialize_map(self, _: Option<usize>) -> Result<Map<'py>, Error> {
        Ok(Map {
            builder: self,
            dict: PyDict::new(self.py),
            key: None,
        })
    }
    fn serialize_struct(self, _: &'static str, len: usize) -> Result<Map<'py>, Error> {
        self.serialize_map(Some(len))
    }
    fn serialize_struct_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeStructVariant, Error> {
        Err(Error::Unsupported("a struct variant"))
    }
}

impl<'py> Seq<'py> {
    fn push<T: Serialize + ?Sized>(&mut self, value: &T) -> Result<(), Error> {
        self.items.push(value.serialize(self.builder)?);
        // A long list (10⁵ events) takes seconds with the GIL held, when Python's own signal
        // handlers cannot run: Ctrl-C is looked for here, as during the run.
        if self.items.len().is_multiple_of(4096) {
            self.builder.py.check_signals()?;
        }
        Ok(())
    }
    fn list(self) -> Built<'py> {
        Ok(PyList::new(self.builder.py, self.items)?.into_any())
    }
}

impl<'py> ser::SerializeSeq for Seq<'py> {
    type Ok = Bound<'py, PyAny>;
    type Error = Error;
    fn serialize_element<T: Serialize + ?Sized>(&mut self, value: &T) -> Result<(), Error> {
        self.push(value)
    }
    fn end(self) -> Built<'py> {
        self.list()
    }
}

impl<'py> ser::SerializeTuple for Seq<'py> {
    type Ok = Bound<'py, PyAny>;
    type Error = Error;
    fn serialize_element<T: Serialize + ?Sized>(&mut self, value: &T) -> Result<(), Error> {
        self.push(value)
    }
    fn end(self) -> Built<'py> {
        self.list()
    }
}

impl<'py> ser::SerializeTupleStruct for Seq<'py> {
    type Ok = Bound<'py, PyAny>;
    type Error = Error;
    fn serialize_field<T: Serialize + ?Sized>(&mut self, value: &T) -> Result<(), Error> {
        self.push(value)
    }
    fn end(self) -> Built<'py> {
        self.list()
    }
}

impl<'py> ser::SerializeMap for Map<'py> {
    type Ok = Bound<'py, PyAny>;
    type Error = Error;
    fn serialize_key<T: Serialize + ?Sized>(&mut self, key: &T) -> Result<(), Error> {
        self.key = Some(key.serialize(self.builder)?);
        Ok(())
    }
    fn serialize_value<T: Serialize + ?Sized>(&mut self, value: &T) -> Result<(), Error> {
        let key = self
            .key
            .take()
            .ok_or(Error::Unsupported("a map value without its key"))?;
        self.dict.set_item(key, value.serialize(self.builder)?)?;
        Ok(())
    }
    fn end(self) -> Built<'py> {
        Ok(self.dict.into_any())
    }
}

impl<'py> ser::SerializeStruct for Map<'py> {
    type Ok = Bound<'py, PyAny>;
    type Error = Error;
    fn serialize_field<T: Serialize + ?Sized>(
        &mut self,
        key: &'static str,
        value: &T,
    ) -> Result<(), Error> {
        self.dict.set_item(key, value.serialize(self.builder)?)?;
        Ok(())
    }
    fn end(self) -> Built<'py> {
        Ok(self.dict.into_any())
    }
}
