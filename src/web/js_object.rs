//! Reading the page's plain objects into typed values: every module's
//! boundary (the player's [`api`](super::api), the camera and board
//! modules' [`camera_api`](super::camera_api)) reads through here, so that
//! an unknown field is refused the same way everywhere, naming it: a typed
//! argument (`Ts<T>`) through [`read_ts`], a nested object's through
//! [`refuse_unknown_fields`] and [`refuse_unknown_fields_of_each`] on its
//! [`field`] before the whole is read.

use serde::de::{self, DeserializeOwned, Deserializer, Visitor};
use tsify::{Ts, Tsify};
use wasm_bindgen::{JsCast, JsValue};

/// A `T` from the page's object `value` (`what` names it in errors); an
/// unknown field of its own refused (a nested object's are checked by the
/// caller).
pub fn read<T: DeserializeOwned>(value: JsValue, what: &str) -> Result<T, String> {
    refuse_unknown_fields::<T>(&value, what)?;
    serde_wasm_bindgen::from_value(value).map_err(|e| format!("{what}: {e}"))
}

/// A `T` from the page's typed object `value`, as [`read`] reads it: the
/// one way a `Ts<T>` argument is read (tsify's own `to_rust` would let an
/// unknown field pass).
pub fn read_ts<T>(value: &Ts<T>, what: &str) -> Result<T, String>
where
    T: DeserializeOwned + Tsify,
    T::JsType: JsCast,
{
    read(value.js_value(), what)
}

/// [`refuse_unknown_fields`] on each object of the list `value` (`what`
/// names the list; an item is named by its index). Anything but a list is
/// left to serde to refuse.
#[cfg(any(feature = "web-camera", feature = "web-board"))]
pub fn refuse_unknown_fields_of_each<T: DeserializeOwned>(value: &JsValue, what: &str) -> Result<(), String> {
    if !js_sys::Array::is_array(value) {
        return Ok(());
    }
    for (i, item) in value.unchecked_ref::<js_sys::Array>().iter().enumerate() {
        refuse_unknown_fields::<T>(&item, &format!("{what}[{i}]"))?;
    }
    Ok(())
}

/// `value[name]`, or `undefined` when `value` is no object: a nested
/// object, for its unknown fields to be refused where it is.
#[cfg(any(feature = "web-camera", feature = "web-board"))]
pub fn field(value: &JsValue, name: &str) -> JsValue {
    js_sys::Reflect::get(value, &JsValue::from_str(name)).unwrap_or_default()
}

/// An error naming a key of the object `value` that `T` has no field for.
/// (serde-wasm-bindgen reads a struct's fields by name and never sees any
/// other, so `deny_unknown_fields` alone would let a misspelt one pass.)
/// Anything but an object is left to serde to refuse.
pub fn refuse_unknown_fields<T: DeserializeOwned>(value: &JsValue, what: &str) -> Result<(), String> {
    let Some(object) = value.dyn_ref::<js_sys::Object>() else { return Ok(()) };
    if value.is_function() || js_sys::Array::is_array(value) {
        return Ok(());
    }
    let known = field_names::<T>();
    for key in js_sys::Object::keys(object).iter() {
        let key = key.as_string().unwrap_or_default();
        if !known.contains(&key.as_str()) {
            return Err(format!("{what}: unknown field `{key}`, expected one of `{}`", known.join("`, `")));
        }
    }
    Ok(())
}

/// The fields a struct's serde derive reads: what it hands the deserializer.
fn field_names<T: DeserializeOwned>() -> &'static [&'static str] {
    let mut fields: &'static [&'static str] = &[];
    let _ = T::deserialize(FieldNames(&mut fields));
    fields
}

/// A deserializer that only records the field names of the struct asked of it.
struct FieldNames<'a>(&'a mut &'static [&'static str]);

impl<'de> Deserializer<'de> for FieldNames<'_> {
    type Error = de::value::Error;

    fn deserialize_any<V: Visitor<'de>>(self, _: V) -> Result<V::Value, Self::Error> {
        Err(de::Error::custom("not a struct"))
    }

    fn deserialize_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        fields: &'static [&'static str],
        _: V,
    ) -> Result<V::Value, Self::Error> {
        *self.0 = fields;
        Err(de::Error::custom("only the field names were wanted"))
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf option unit
        unit_struct newtype_struct seq tuple tuple_struct map enum identifier ignored_any
    }
}
