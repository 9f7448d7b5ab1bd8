//! parol6-core
