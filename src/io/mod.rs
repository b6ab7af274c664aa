//! Writing outputs: files written whole or not at all, standard output, and the rows of a
//! table.

pub mod comment;
pub mod output;
pub(crate) mod rows;
pub mod size;
pub mod unique_keys;
