//! Columns written as one Parquet file (feature `parquet`; arrow-rs, Snappy only): the
//! command's `records.parquet` and `frames.parquet` (`scene::parquet`) and the scenes' tables.
//! Every f64 is stored as written, so a reader gets the values bit for bit; measured columns
//! (few repeated values) are written BYTE_STREAM_SPLIT without a dictionary
//! ([`Table::f64_measured`]), which groups the slowly varying sign, exponent and leading
//! mantissa bytes where Snappy finds them.

use super::{OutputError, write_atomic};
use arrow_array::{ArrayRef, Float64Array, Int64Array, RecordBatch, StringArray, UInt64Array};
use arrow_schema::{DataType, Field, Schema};
use parquet::arrow::ArrowWriter;
use parquet::basic::{Compression, Encoding};
use parquet::file::properties::WriterProperties;
use parquet::schema::types::ColumnPath;
use std::path::Path;
use std::sync::Arc;

fn failed(e: impl std::fmt::Display) -> OutputError {
    OutputError::Parquet(e.to_string())
}

/// Columns by name, written atomically as one Parquet file.
#[derive(Default)]
pub struct Table {
    fields: Vec<Field>,
    columns: Vec<ArrayRef>,
    /// Columns written BYTE_STREAM_SPLIT without a dictionary.
    split: Vec<String>,
}

impl Table {
    /// A column of f64 values.
    pub fn f64(&mut self, name: &str, v: Vec<f64>) {
        self.fields.push(Field::new(name, DataType::Float64, false));
        self.columns.push(Arc::new(Float64Array::from(v)));
    }

    /// A column of measured values (few repeats): BYTE_STREAM_SPLIT, no dictionary.
    pub fn f64_measured(&mut self, name: &str, v: Vec<f64>) {
        self.split.push(name.to_string());
        self.f64(name, v);
    }

    /// A column of f64 values, `None` written as null.
    pub fn f64_or_null(&mut self, name: &str, v: Vec<Option<f64>>) {
        self.fields.push(Field::new(name, DataType::Float64, true));
        self.columns.push(Arc::new(Float64Array::from(v)));
    }

    /// A column of integers.
    pub fn i64(&mut self, name: &str, v: Vec<i64>) {
        self.fields.push(Field::new(name, DataType::Int64, false));
        self.columns.push(Arc::new(Int64Array::from(v)));
    }

    /// A column of integers, `None` written as null.
    pub fn i64_or_null(&mut self, name: &str, v: Vec<Option<i64>>) {
        self.fields.push(Field::new(name, DataType::Int64, true));
        self.columns.push(Arc::new(Int64Array::from(v)));
    }

    /// A column of unsigned integers.
    pub fn u64(&mut self, name: &str, v: Vec<u64>) {
        self.fields.push(Field::new(name, DataType::UInt64, false));
        self.columns.push(Arc::new(UInt64Array::from(v)));
    }

    /// A column of strings, `None` written as null.
    pub fn text(&mut self, name: &str, v: Vec<Option<String>>) {
        self.fields.push(Field::new(name, DataType::Utf8, true));
        self.columns.push(Arc::new(StringArray::from(v)));
    }

    /// Write the columns as one row group to `path`, atomically (Snappy).
    pub fn write(self, path: &Path) -> Result<(), OutputError> {
        let schema = Arc::new(Schema::new(self.fields));
        let batch = RecordBatch::try_new(schema.clone(), self.columns).map_err(failed)?;
        let props = self
            .split
            .into_iter()
            .fold(
                WriterProperties::builder().set_compression(Compression::SNAPPY),
                |props, name| {
                    let column = ColumnPath::from(name);
                    props
                        .set_column_dictionary_enabled(column.clone(), false)
                        .set_column_encoding(column, Encoding::BYTE_STREAM_SPLIT)
                },
            )
            .build();
        let mut bytes = Vec::new();
        let mut writer = ArrowWriter::try_new(&mut bytes, schema, Some(props)).map_err(failed)?;
        writer.write(&batch).map_err(failed)?;
        let _ = writer.close().map_err(failed)?;
        write_atomic(path, &bytes)
    }
}
