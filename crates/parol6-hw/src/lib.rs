//! parol6-hw
