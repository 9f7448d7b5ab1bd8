//! Pre-flight of a whole program (filled in with the pre-flight checker).
