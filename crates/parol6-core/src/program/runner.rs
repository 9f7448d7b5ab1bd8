//! Program runner (next).
