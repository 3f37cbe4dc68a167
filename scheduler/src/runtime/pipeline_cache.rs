//! Compiled pipelines kept across runs of a program: a `wgpu::PipelineCache`
//! per adapter, driver and module, loaded from and saved to a directory of
//! files ([`ExecutorConfig::pipeline_cache_dir`](crate::ExecutorConfig::pipeline_cache_dir)).
//!
//! A file is named `{key}-{driver}-{module}.wgpucache`: `key` is
//! [`wgpu::util::pipeline_cache_key`] (backend, vendor and device), `driver`
//! an FNV-1a hash of the driver's name and version string, `module` an FNV-1a
//! hash of the module's WGSL. It holds a header of ours (magic, the module
//! hash, a hash of the payload) and then what
//! [`wgpu::PipelineCache::get_data`] returned, whose own header wgpu checks
//! (adapter, driver version, length). A file that fails either check is
//! ignored with a warning and replaced. The directory keeps at most
//! [`MAX_FILES`] files and [`MAX_BYTES`] bytes of them: the least recently
//! used go first.

use std::fs;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, SystemTime};

/// Most cache files a directory keeps.
pub const MAX_FILES: usize = 64;

/// Most bytes of cache files a directory keeps (256 MiB).
pub const MAX_BYTES: u64 = 256 << 20;

/// The extension of a cache file.
const EXTENSION: &str = "wgpucache";

/// What every cache file name starts with (that of
/// [`wgpu::util::pipeline_cache_key`]).
const PREFIX: &str = "wgpu_pipeline_cache_";

/// The first bytes of a cache file.
const MAGIC: [u8; 8] = *b"SCHPLC01";

/// Magic, module hash, payload hash.
const HEADER_BYTES: usize = 24;

/// What the executor did with its pipeline cache.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum PipelineCacheState {
    /// A directory was configured but the device cannot cache pipelines
    /// (it lacks [`wgpu::Features::PIPELINE_CACHE`], or its backend has no
    /// cache key): pipelines were created without a cache.
    Unsupported,
    /// No directory was configured
    /// ([`ExecutorConfig::pipeline_cache_dir`](crate::ExecutorConfig::pipeline_cache_dir)).
    Off,
    /// No file for this adapter, driver and module yet: the pipelines were
    /// created from scratch and saved.
    Miss,
    /// The file was loaded and accepted: the driver was given its data.
    Hit,
    /// A file was there but could not be used (the reason); it was ignored
    /// and replaced.
    Rejected(String),
}

/// How long the driver took to compile the megakernel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CompileTimings {
    /// Creating the shader module and the megakernel pipeline (where most
    /// drivers compile; lavapipe translates SPIR-V to NIR here).
    pub pipeline_creation: Duration,
    /// The first dispatch of the megakernel, a dispatch of no workgroups
    /// that [`Executor::new`](crate::Executor::new) submits and waits for:
    /// drivers that compile lazily (llvmpipe runs LLVM here) compile then
    /// instead of in the first run. `None` when it could not be submitted.
    pub first_dispatch: Option<Duration>,
}

/// A stable 64-bit FNV-1a hash (the same on every platform and Rust
/// version, unlike `std::hash::DefaultHasher`).
pub fn fnv1a_64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |hash, &byte| {
        (hash ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// The name of the cache file for `wgsl` on the adapter `info`; `None` when
/// its backend has no pipeline cache.
pub fn file_name(info: &wgpu::AdapterInfo, wgsl: &str) -> Option<String> {
    let key = wgpu::util::pipeline_cache_key(info)?;
    let driver = fnv1a_64(format!("{}\n{}", info.driver, info.driver_info).as_bytes());
    let module = fnv1a_64(wgsl.as_bytes());
    Some(format!("{key}-{driver:016x}-{module:016x}.{EXTENSION}"))
}

/// Whether `name` is the name of a cache file (or of one being written)
/// that this module writes; other files in the directory are never touched.
pub fn is_cache_file_name(name: &str) -> bool {
    name.starts_with(PREFIX)
        && (name.ends_with(&format!(".{EXTENSION}")) || name.contains(&format!(".{EXTENSION}.tmp")))
}

/// The cache of one executor and the file it is saved to.
#[derive(Debug)]
pub(crate) struct DiskCache {
    pub(crate) cache: wgpu::PipelineCache,
    path: PathBuf,
    module_hash: u64,
    /// Length and hash of the data last saved (or loaded).
    saved: Option<(usize, u64)>,
}

/// Opens the cache for `wgsl` in `dir`: loads its file if there is a good
/// one, else starts an empty cache.
pub(crate) fn open(
    device: &wgpu::Device,
    dir: Option<&Path>,
    wgsl: &str,
) -> (PipelineCacheState, Option<DiskCache>) {
    let Some(dir) = dir else {
        return (PipelineCacheState::Off, None);
    };
    let info = device.adapter_info();
    let name = file_name(&info, wgsl);
    let Some(name) = name.filter(|_| device.features().contains(wgpu::Features::PIPELINE_CACHE))
    else {
        log::info!(
            "pipeline cache: `{}` ({:?}) cannot cache pipelines; running without",
            info.name,
            info.backend
        );
        return (PipelineCacheState::Unsupported, None);
    };
    let path = dir.join(name);
    let module_hash = fnv1a_64(wgsl.as_bytes());
    let mut state = PipelineCacheState::Miss;
    let mut saved = None;
    let loaded = match fs::read(&path) {
        Ok(bytes) => match payload(&bytes, module_hash) {
            Ok(data) => match create(device, Some(data)) {
                Ok(cache) => {
                    saved = Some((data.len(), fnv1a_64(data)));
                    Some(cache)
                }
                Err(reason) => {
                    state = PipelineCacheState::Rejected(reason);
                    None
                }
            },
            Err(reason) => {
                state = PipelineCacheState::Rejected(reason.to_owned());
                None
            }
        },
        Err(error) if error.kind() == io::ErrorKind::NotFound => None,
        Err(error) => {
            state = PipelineCacheState::Rejected(format!("unreadable: {error}"));
            None
        }
    };
    let cache = match loaded {
        Some(cache) => {
            state = PipelineCacheState::Hit;
            touch(&path);
            cache
        }
        None => {
            if let PipelineCacheState::Rejected(reason) = &state {
                log::warn!(
                    "pipeline cache: ignoring {} ({reason}); it will be replaced",
                    path.display()
                );
            }
            match create(device, None) {
                Ok(cache) => cache,
                Err(reason) => {
                    log::warn!("pipeline cache: cannot create one ({reason}); running without");
                    return (PipelineCacheState::Unsupported, None);
                }
            }
        }
    };
    log::debug!("pipeline cache: {state:?} for {}", path.display());
    (
        state,
        Some(DiskCache {
            cache,
            path,
            module_hash,
            saved,
        }),
    )
}

/// The wgpu data of a file, after our header's checks.
fn payload(bytes: &[u8], module_hash: u64) -> Result<&[u8], &'static str> {
    let (header, data) = bytes
        .split_at_checked(HEADER_BYTES)
        .ok_or("truncated: shorter than its header")?;
    let word = |at: usize| {
        let mut le = [0; 8];
        le.copy_from_slice(&header[at..at + 8]);
        u64::from_le_bytes(le)
    };
    if header[..8] != MAGIC {
        return Err("not a pipeline cache file of this program");
    }
    if word(8) != module_hash {
        return Err("written for another module");
    }
    if word(16) != fnv1a_64(data) {
        return Err("corrupt: its data does not match its hash");
    }
    Ok(data)
}

/// A pipeline cache with `data`, or the reason the device refused it.
fn create(device: &wgpu::Device, data: Option<&[u8]>) -> Result<wgpu::PipelineCache, String> {
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    // SAFETY: `data` is only ever what `PipelineCache::get_data` returned
    // for a file of the same name, i.e. the same `pipeline_cache_key`,
    // driver and module: `payload` checked our header (the module hash and
    // a hash of the data, so a truncated, corrupt or foreign file never
    // gets here), and wgpu-core checks its own header (magic, adapter key,
    // driver version, length) before the driver sees it. With `fallback:
    // false` a failure of that check is an error we report, not a silent
    // empty cache.
    #[expect(
        unsafe_code,
        reason = "the data is what get_data wrote for this key, see the comment above"
    )]
    let cache = unsafe {
        device.create_pipeline_cache(&wgpu::PipelineCacheDescriptor {
            label: Some("scheduler pipelines"),
            data,
            fallback: false,
        })
    };
    match pollster::block_on(scope.pop()) {
        Some(error) => Err(error.to_string()),
        None => Ok(cache),
    }
}

impl DiskCache {
    /// Saves the cache's data when it changed since the last save; returns
    /// whether it wrote. A failure is a warning: the run goes on.
    pub(crate) fn save(&mut self) -> bool {
        let Some(data) = self.cache.get_data() else {
            return false;
        };
        let stamp = (data.len(), fnv1a_64(&data));
        if self.saved == Some(stamp) {
            return false;
        }
        let mut bytes = Vec::with_capacity(HEADER_BYTES + data.len());
        bytes.extend_from_slice(&MAGIC);
        bytes.extend_from_slice(&self.module_hash.to_le_bytes());
        bytes.extend_from_slice(&stamp.1.to_le_bytes());
        bytes.extend_from_slice(&data);
        match write_atomically(&self.path, &bytes) {
            Ok(()) => {
                log::debug!(
                    "pipeline cache: saved {} bytes to {}",
                    bytes.len(),
                    self.path.display()
                );
                self.saved = Some(stamp);
                if let Some(dir) = self.path.parent() {
                    evict(dir, &self.path, MAX_FILES, MAX_BYTES);
                }
                true
            }
            Err(error) => {
                log::warn!(
                    "pipeline cache: cannot write {} ({error}); pipelines are not kept",
                    self.path.display()
                );
                false
            }
        }
    }
}

/// Writes `bytes` to a temporary file beside `path`, then renames it over
/// `path`: a crash leaves the old file or the new one, never half of one.
fn write_atomically(path: &Path, bytes: &[u8]) -> io::Result<()> {
    let dir = path.parent().unwrap_or(Path::new("."));
    fs::create_dir_all(dir)?;
    // Unique per process and per write, so concurrent writers never share
    // a temporary file.
    static WRITES: AtomicU64 = AtomicU64::new(0);
    let mut temp = path.as_os_str().to_owned();
    temp.push(format!(
        ".tmp{}-{}",
        std::process::id(),
        WRITES.fetch_add(1, Ordering::Relaxed)
    ));
    let temp = PathBuf::from(temp);
    let written = fs::write(&temp, bytes).and_then(|()| fs::rename(&temp, path));
    if written.is_err() {
        // Best effort: the temporary file may not even exist.
        let _ = fs::remove_file(&temp);
    }
    written
}

/// Marks `path` as just used, for the eviction order.
fn touch(path: &Path) {
    let touched = fs::File::options()
        .append(true)
        .open(path)
        .and_then(|file| file.set_modified(SystemTime::now()));
    if let Err(error) = touched {
        log::debug!("pipeline cache: cannot touch {} ({error})", path.display());
    }
}

/// Removes the least recently used cache files of `dir` (never `keep`)
/// until at most `max_files` files and `max_bytes` bytes are left.
pub(crate) fn evict(dir: &Path, keep: &Path, max_files: usize, max_bytes: u64) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    let mut files: Vec<(SystemTime, u64, PathBuf)> = entries
        .flatten()
        .filter(|entry| {
            entry
                .file_name()
                .to_str()
                .is_some_and(|name| is_cache_file_name(name) && name.ends_with(EXTENSION))
        })
        .filter_map(|entry| {
            let meta = entry.metadata().ok()?;
            let used = meta.modified().unwrap_or(SystemTime::UNIX_EPOCH);
            Some((used, meta.len(), entry.path()))
        })
        .collect();
    // Oldest first; the file just written is never a candidate.
    files.sort();
    let mut count = files.len();
    let mut total: u64 = files.iter().map(|(_, len, _)| len).sum();
    for (_, len, path) in &files {
        if count <= max_files && total <= max_bytes {
            break;
        }
        if path == keep {
            continue;
        }
        match fs::remove_file(path) {
            Ok(()) => {
                log::debug!("pipeline cache: evicted {}", path.display());
                count -= 1;
                total -= len;
            }
            Err(error) => log::warn!("pipeline cache: cannot evict {} ({error})", path.display()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_dir(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!(
            "scheduler-pipeline-cache-{name}-{}",
            std::process::id()
        ));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn fnv1a_matches_the_reference_values() {
        assert_eq!(fnv1a_64(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a_64(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a_64(b"foobar"), 0x8594_4171_f739_67e8);
    }

    #[test]
    fn names_encode_the_adapter_driver_and_module() {
        let info = wgpu::AdapterInfo {
            name: "llvmpipe".into(),
            vendor: 0x10005,
            device: 0,
            device_type: wgpu::DeviceType::Cpu,
            device_pci_bus_id: String::new(),
            driver: "llvmpipe".into(),
            driver_info: "Mesa 25.0".into(),
            backend: wgpu::Backend::Vulkan,
            subgroup_min_size: 4,
            subgroup_max_size: 8,
            transient_saves_memory: None,
            limit_bucket: None,
        };
        let name = file_name(&info, "fn main() {}").unwrap();
        assert!(name.starts_with("wgpu_pipeline_cache_vulkan_65541_0-"));
        assert!(is_cache_file_name(&name));
        assert_ne!(name, file_name(&info, "fn main() { }").unwrap());
        let updated = wgpu::AdapterInfo {
            driver_info: "Mesa 25.1".into(),
            ..info.clone()
        };
        assert_ne!(name, file_name(&updated, "fn main() {}").unwrap());
        let gl = wgpu::AdapterInfo {
            backend: wgpu::Backend::Gl,
            ..info
        };
        assert_eq!(file_name(&gl, "fn main() {}"), None);
        assert!(!is_cache_file_name("index.html"));
        assert!(!is_cache_file_name("wgpu_pipeline_cache_notes.txt"));
        assert!(is_cache_file_name(&format!("{name}.tmp42")));
    }

    #[test]
    fn headers_reject_foreign_truncated_and_corrupt_files() {
        let data = b"driver data".as_slice();
        let mut file = MAGIC.to_vec();
        file.extend_from_slice(&7u64.to_le_bytes());
        file.extend_from_slice(&fnv1a_64(data).to_le_bytes());
        file.extend_from_slice(data);
        assert_eq!(payload(&file, 7), Ok(data));
        assert_eq!(payload(&file, 8), Err("written for another module"));
        assert!(
            payload(&file[..10], 7)
                .unwrap_err()
                .starts_with("truncated")
        );
        assert!(payload(&file[..30], 7).unwrap_err().starts_with("corrupt"));
        let mut flipped = file.clone();
        *flipped.last_mut().unwrap() ^= 1;
        assert!(payload(&flipped, 7).unwrap_err().starts_with("corrupt"));
        assert!(payload(b"garbage garbage garbage garbage", 7).is_err());
    }

    #[test]
    fn eviction_keeps_the_most_recent_files_within_the_caps() {
        let dir = temp_dir("evict");
        let name = |i: u32| format!("{PREFIX}vulkan_1_2-{i:016x}-0.{EXTENSION}");
        let start = SystemTime::now() - Duration::from_secs(1000);
        for i in 0..6u32 {
            let path = dir.join(name(i));
            fs::write(&path, vec![0u8; 100]).unwrap();
            let file = fs::File::options().append(true).open(&path).unwrap();
            file.set_modified(start + Duration::from_secs(u64::from(i)))
                .unwrap();
        }
        fs::write(dir.join("notes.txt"), "not ours").unwrap();
        // The oldest is the one just written: it stays anyway.
        evict(&dir, &dir.join(name(0)), 4, u64::MAX);
        let mut left: Vec<String> = fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        left.sort();
        let mut expected = vec![name(0), name(3), name(4), name(5), "notes.txt".to_owned()];
        expected.sort();
        assert_eq!(left, expected);
        // The byte cap: 250 bytes hold two files of 100.
        evict(&dir, &dir.join(name(5)), 64, 250);
        assert!(dir.join(name(4)).exists() && dir.join(name(5)).exists());
        assert!(!dir.join(name(0)).exists() && !dir.join(name(3)).exists());
        assert!(dir.join("notes.txt").exists());
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn an_unwritable_directory_is_an_error_not_a_panic() {
        let dir = temp_dir("unwritable");
        let blocker = dir.join("file");
        fs::write(&blocker, "a file, not a directory").unwrap();
        let path = blocker.join("cache.wgpucache");
        assert!(write_atomically(&path, b"data").is_err());
        fs::remove_dir_all(&dir).unwrap();
    }
}
