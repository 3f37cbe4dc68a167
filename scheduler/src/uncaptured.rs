//! The errors of a device that no error scope caught.
//!
//! wgpu hands such an error (a validation error of a command the caller did
//! not wrap in `push_error_scope`, an out-of-memory) to the device's
//! uncaptured-error handler, whose default panics: a library must not end
//! its caller's process on a bad input. [`UncapturedErrors::install`]
//! replaces it with one that logs the error and records it, so that the
//! code that submitted the work returns it as an error
//! ([`UncapturedErrors::take`]).

use std::sync::{Arc, Mutex, PoisonError};

/// Most messages kept between two [`UncapturedErrors::take`]s; the others
/// are counted.
const KEPT: usize = 4;

/// What the handler recorded since the last take.
#[derive(Debug, Default)]
struct Recorded {
    messages: Vec<String>,
    dropped: usize,
}

/// The uncaptured errors of one device, shared with its handler.
#[derive(Debug, Clone, Default)]
pub struct UncapturedErrors(Arc<Mutex<Recorded>>);

impl UncapturedErrors {
    /// Installs the handler on `device` (replacing wgpu's, which panics)
    /// and returns the record it fills.
    pub fn install(device: &wgpu::Device) -> Self {
        let errors = Self::default();
        let record = errors.clone();
        device.on_uncaptured_error(Arc::new(move |error: wgpu::Error| {
            log::error!("uncaptured GPU error: {error}");
            record.push(error.to_string());
        }));
        errors
    }

    fn push(&self, message: String) {
        let mut recorded = self.0.lock().unwrap_or_else(PoisonError::into_inner);
        if recorded.messages.len() < KEPT {
            recorded.messages.push(message);
        } else {
            recorded.dropped += 1;
        }
    }

    /// The errors recorded since the last call, in one message (the first
    /// ones, the others counted), or `None`; the record is emptied.
    pub fn take(&self) -> Option<String> {
        let recorded = std::mem::take(&mut *self.0.lock().unwrap_or_else(PoisonError::into_inner));
        if recorded.messages.is_empty() {
            return None;
        }
        let mut text = recorded.messages.join("; ");
        if recorded.dropped > 0 {
            text.push_str(&format!(" (and {} more)", recorded.dropped));
        }
        Some(text)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn take_joins_the_first_messages_and_counts_the_rest() {
        let errors = UncapturedErrors::default();
        assert_eq!(errors.take(), None);
        for i in 0..KEPT + 2 {
            errors.push(format!("e{i}"));
        }
        assert_eq!(
            errors.take().as_deref(),
            Some("e0; e1; e2; e3 (and 2 more)")
        );
        assert_eq!(errors.take(), None, "emptied");
    }
}
