//! The framework's text format, read into a [`Scene`](crate::scene::Scene).
//!
//! A file is a sequence of blocks (`background`, `camera`, `light TYPE`,
//! `primitive TYPE`), each closed by `end`, holding `key= values` lines; see
//! `docs/format.md` for every key. The [`reader`] splits the text into
//! blocks, the [`builder`] checks each against its row of the [`schema`] and
//! builds it ([`blocks`], [`shapes`]), loading the files it names
//! ([`assets`], [`obj`]); every problem becomes a diagnostic with its place.

mod assets;
mod block;
mod blocks;
mod builder;
mod diags;
mod lexer;
mod obj;
mod reader;
mod schema;
mod shapes;
mod suggest;
mod values;

#[cfg(test)]
pub(crate) use obj::load_obj;
pub(crate) use reader::{parse_file, parse_str};
