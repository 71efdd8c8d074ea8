//! The server-sent events: each page's event stream is a bounded channel;
//! a stream that falls behind is dropped (its page reconnects and reads
//! the state afresh), so a stalled browser never holds the renderer up.

use std::sync::Mutex;
use std::sync::mpsc::{Receiver, SyncSender, sync_channel};

/// Events a stream may have waiting before it is dropped.
const BACKLOG: usize = 64;

/// One event as the stream sends it: `event: NAME` and `data: JSON`.
pub(crate) type Event = String;

/// The open event streams.
#[derive(Default)]
pub(crate) struct Events {
    streams: Mutex<Vec<SyncSender<Event>>>,
}

impl Events {
    /// A new stream's receiving end.
    pub fn subscribe(&self) -> Receiver<Event> {
        let (tx, rx) = sync_channel(BACKLOG);
        self.lock().push(tx);
        rx
    }

    /// The streams, locked.
    fn lock(&self) -> std::sync::MutexGuard<'_, Vec<SyncSender<Event>>> {
        self.streams.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Sends event `name` with `data` (one line of JSON) to every stream.
    pub fn send(&self, name: &str, data: &str) {
        let event = format(name, data);
        self.lock().retain(|tx| tx.try_send(event.clone()).is_ok());
    }
}

/// The wire form of an event (`data` must hold no line break: JSON as
/// serde_json writes it holds none).
pub(crate) fn format(name: &str, data: &str) -> Event {
    format!("event: {name}\ndata: {data}\n\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn events_reach_each_stream_and_a_stalled_one_is_dropped() {
        let events = Events::default();
        let a = events.subscribe();
        let b = events.subscribe();
        events.send("state", "{}");
        assert_eq!(
            a.try_recv().ok().as_deref(),
            Some("event: state\ndata: {}\n\n")
        );
        assert!(b.try_recv().is_ok());
        // `a` reads on; `b` stops reading and is dropped once its backlog is full.
        for _ in 0..BACKLOG + 1 {
            events.send("progress", "{}");
            assert!(a.try_recv().is_ok());
        }
        assert_eq!(events.lock().len(), 1);
        drop(a);
        events.send("state", "{}");
        assert_eq!(events.lock().len(), 0);
        assert!(b.try_recv().is_ok());
    }
}
