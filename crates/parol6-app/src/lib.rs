//! parol6-app
