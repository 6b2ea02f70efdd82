//! Watching the open file for changes, on a thread of its own (natively: a page has no files
//! on disk to watch).

use crate::platform::Duration;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::SystemTime;

/// How often the open file is checked for changes on disk.
const WATCH_INTERVAL: Duration = Duration::from_millis(500);

/// Watches a file on a thread of its own, which wakes the UI only when the file changed: an
/// idle app does not repaint to poll it. The thread ends when the watch is dropped.
pub(super) struct Watch {
    pub(super) path: PathBuf,
    pub(super) changed: std::sync::mpsc::Receiver<()>,
    stop: Arc<std::sync::atomic::AtomicBool>,
}

impl Watch {
    pub(super) fn start(path: &Path, repaint: Arc<dyn Fn() + Send + Sync>) -> Watch {
        use std::sync::atomic::{AtomicBool, Ordering};
        let (tx, rx) = std::sync::mpsc::channel();
        let stop = Arc::new(AtomicBool::new(false));
        let stopped = Arc::clone(&stop);
        let file = path.to_path_buf();
        let mut stamp = modified(&file);
        let running = Arc::clone(&stop);
        // Never joined: it ends on its own once the watch is dropped (or the app gone).
        let _ticker = crate::platform::spawn_ticker(
            WATCH_INTERVAL,
            move || !running.load(Ordering::Relaxed),
            move || {
                let m = modified(&file);
                if m != stamp {
                    stamp = m;
                    if stopped.load(Ordering::Relaxed) || tx.send(()).is_err() {
                        stopped.store(true, Ordering::Relaxed);
                        return;
                    }
                    repaint();
                }
            },
        );
        Watch {
            path: path.to_path_buf(),
            changed: rx,
            stop,
        }
    }
}

impl Drop for Watch {
    fn drop(&mut self) {
        self.stop.store(true, std::sync::atomic::Ordering::Relaxed);
    }
}

pub(super) fn modified(path: &Path) -> Option<SystemTime> {
    std::fs::metadata(path).and_then(|m| m.modified()).ok()
}
