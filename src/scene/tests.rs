//! Tests of scene parsing and tailoring.
