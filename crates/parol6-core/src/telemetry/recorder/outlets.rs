//! The recorder's handles for other threads: the live outlets a live server reads every sample
//! and event from ([`LiveOutlet`]), and the handle that adds events ([`RecorderEvents`]). Both
//! only `try_send`: a full channel drops and counts, nothing here waits on the recorder.

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use crossbeam_channel::{Receiver, Sender, TrySendError};

use super::{Control, Shared};
use crate::telemetry::event::{EventKind, TelemetryEvent};
use crate::telemetry::sample::TelemetrySample;

/// What a [`LiveOutlet`] carries.
#[derive(Debug, Clone)]
pub enum LiveItem {
    /// One control tick (every sample the backend delivered while the outlet is open).
    Sample(Arc<TelemetrySample>),
    /// An event (limit warning, refusal, E-stop, link loss, program step, network command …).
    Event(TelemetryEvent),
}

/// The recorder's end of a live outlet.
pub(super) struct Outlet {
    pub(super) tx: Sender<LiveItem>,
    pub(super) dropped: Arc<AtomicU64>,
}

/// A live server's end of an outlet of the recorder: every sample and event from now on, through
/// a bounded channel (see the module docs). Dropping it closes the outlet.
#[derive(Debug)]
pub struct LiveOutlet {
    /// The samples and events, in order.
    pub rx: Receiver<LiveItem>,
    pub(super) dropped: Arc<AtomicU64>,
}

impl LiveOutlet {
    /// Items the recorder dropped because this outlet was full.
    pub fn dropped(&self) -> u64 {
        self.dropped.load(Ordering::Relaxed)
    }
}

/// A cloneable handle that adds events to a recorder's `/events` (from any thread, never
/// blocking: a full control channel drops the event and counts it).
#[derive(Debug, Clone)]
pub struct RecorderEvents {
    pub(super) control: Sender<Control>,
    pub(super) shared: Arc<Shared>,
}

impl RecorderEvents {
    /// Records an event (a NaN time takes the latest sample's).
    pub fn event(&self, event: TelemetryEvent) {
        send_control(&self.control, &self.shared, Control::Event(event));
    }

    /// Records a note (`EventKind::Note`) with `message`, at the latest sample's time.
    pub fn note(&self, message: impl Into<String>) {
        self.event(TelemetryEvent { time_s: f64::NAN, kind: EventKind::Note, message: message.into() });
    }
}

pub(super) fn send_control(control: &Sender<Control>, shared: &Shared, c: Control) {
    if let Err(TrySendError::Full(_) | TrySendError::Disconnected(_)) = control.try_send(c) {
        shared.counters.control_dropped.fetch_add(1, Ordering::Relaxed);
    }
}
