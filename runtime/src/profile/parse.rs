//! Reading a profile: a number is a constant, a table is a [`ShapedProfile`] by its `kind`.

use super::function::{Profile, ShapedProfile};
use serde::Deserialize;
use serde::de::{self, Deserializer, MapAccess, Visitor};
use std::fmt;

impl<'de> Deserialize<'de> for Profile {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct ProfileVisitor;
        impl<'de> Visitor<'de> for ProfileVisitor {
            type Value = Profile;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str(
                    "a number, or a table with kind = \"constant\", \"piecewise-constant\", \
                     \"piecewise-linear\", \"piecewise-cubic\", \"smoothstep\", \"s-curve\", \
                     \"jerk-segments\", \"shaped\" or \"position-schedule\"",
                )
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Profile, E> {
                Ok(Profile::Constant(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Profile, E> {
                Ok(Profile::Constant(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Profile, E> {
                Ok(Profile::Constant(v as f64))
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Profile, A::Error> {
                ShapedProfile::deserialize(de::value::MapAccessDeserializer::new(map))
                    .map(Profile::Shaped)
            }
        }
        deserializer.deserialize_any(ProfileVisitor)
    }
}
