//! Kubernetes YAML: an Indexed Job whose pod I renders tile I (the index
//! from `JOB_COMPLETION_INDEX`), and a Job that waits for every tile and
//! merges them. Paths are those inside the pods, on a claim every pod mounts.

use super::error::{JobError, unfit};
use super::plan::{TileJob, Word, default_name, text};

/// Tries of one index before it counts as failed (other indices go on).
const BACKOFF_PER_INDEX: u32 = 3;

/// Pods the Indexed Job runs at once when not told: this, or fewer tiles.
const DEFAULT_PARALLELISM: u32 = 16;

/// Where the pods run and what each gets.
#[derive(Clone, Debug)]
pub struct K8sOptions {
    /// The container image (glint on its PATH, a POSIX shell).
    pub image: String,
    /// The PersistentVolumeClaim holding the scene, tiles and output.
    pub claim: String,
    /// Where the claim is mounted in every pod (absolute).
    pub mount: String,
    /// The render Job's name (a DNS label) [default: [`default_name`] made one]; the merge's is this and `-merge`.
    pub name: Option<String>,
    /// Pods at once [default: 16, or the tile count when fewer].
    pub parallelism: Option<u32>,
    /// CPUs each render pod asks for, and its threads (the merge asks for one).
    pub cpus: u32,
    /// Memory each pod asks for, a Kubernetes quantity (`4Gi`).
    pub memory: Option<String>,
}

/// The two Jobs, as one multi-document YAML for `kubectl apply -f`.
pub fn k8s_manifests(job: &TileJob, options: &K8sOptions) -> Result<String, JobError> {
    let name = match &options.name {
        Some(name) => label("--name", name)?.to_string(),
        None => dns_label(&default_name(job.output.as_ref())),
    };
    text("--image", &options.image)?;
    text("--claim", &options.claim)?;
    text("--mount", &options.mount)?;
    if let Some(memory) = &options.memory {
        text("--mem", memory)?;
    }
    if !options.mount.starts_with('/') {
        return Err(unfit(
            "--mount",
            &options.mount,
            "a mount path must be absolute",
        ));
    }
    let n = job.tiles;
    let parallelism = options.parallelism.unwrap_or(DEFAULT_PARALLELISM.min(n));
    let tile = Word::Engine(format!("$(JOB_COMPLETION_INDEX)/{n}"));
    let threads = options.cpus.to_string();
    let render = job.render_command(tile, Some(Word::text(threads)));
    let make_dir = [
        Word::text("mkdir"),
        Word::text("-p"),
        Word::text(&job.tiles_dir),
    ];
    let wait = [
        Word::text("sh"),
        Word::text("-c"),
        Word::text("until \"$0\" tiles \"$1\" > /dev/null 2>&1; do sleep 10; done"),
        Word::text(&job.glint),
        Word::text(&job.tiles_dir),
    ];
    let pod = Pod(options);

    let mut s = format!(
        "# Written by `glint job k8s`: `kubectl apply -f` it. The Indexed Job\n\
         # {name} renders\n\
         #   {}\n\
         # in {n} tiles; the Job {name}-merge waits for them and writes\n\
         #   {}\n\
         # The scene, its textures and meshes, the tiles and the output live on\n\
         # the claim {}, mounted at {} in every pod.\n",
        job.scene, job.output, options.claim, options.mount
    );
    s.push_str(&format!(
        "apiVersion: batch/v1\nkind: Job\nmetadata:\n  name: {}\nspec:\n\
         \x20 completionMode: Indexed\n  completions: {n}\n  parallelism: {parallelism}\n\
         \x20 backoffLimitPerIndex: {BACKOFF_PER_INDEX}\n\
         \x20 podFailurePolicy:\n    rules:\n\
         \x20     # Exit 2 is bad input (the scene, an option): retrying cannot help.\n\
         \x20     - action: FailJob\n        onExitCodes:\n          containerName: render\n\
         \x20         operator: In\n          values: [2]\n\
         \x20     # An evicted or preempted pod is not the tile's fault: run it again.\n\
         \x20     - action: Ignore\n        onPodConditions:\n          - type: DisruptionTarget\n",
        quoted(&name)
    ));
    s.push_str(&pod.template(options.cpus, ("tiles-dir", &make_dir), ("render", &render)));
    s.push_str(&format!(
        "---\napiVersion: batch/v1\nkind: Job\nmetadata:\n  name: {}\nspec:\n  backoffLimit: 2\n",
        quoted(&format!("{name}-merge"))
    ));
    // The merge asks for one CPU: it holds it while it waits.
    let merge = job.merge_command();
    s.push_str(&pod.template(1, ("wait-for-tiles", &wait), ("merge", &merge)));
    Ok(s)
}

/// What both Jobs' pods share: the image, the claim, the resources.
struct Pod<'a>(&'a K8sOptions);

impl Pod<'_> {
    /// A pod template (`restartPolicy: Never`) of `cpus` CPUs running
    /// `init`, then `main`, each a container's name and command, with the
    /// claim mounted.
    fn template(&self, cpus: u32, init: (&str, &[Word]), main: (&str, &[Word])) -> String {
        let o = self.0;
        let mut s = String::from("  template:\n    spec:\n      restartPolicy: Never\n");
        for (key, (name, command)) in [("initContainers", init), ("containers", main)] {
            s.push_str(&format!("      {key}:\n        - name: {name}\n"));
            s.push_str(&format!(
                "          image: {}\n          command:\n",
                quoted(&o.image)
            ));
            for word in command {
                s.push_str(&format!("            - {}\n", quoted(&expanded(word))));
            }
            s.push_str("          resources:\n            requests:\n");
            s.push_str(&format!(
                "              cpu: {}\n",
                quoted(&cpus.to_string())
            ));
            if let Some(memory) = &o.memory {
                s.push_str(&format!("              memory: {}\n", quoted(memory)));
            }
            s.push_str("          volumeMounts:\n            - name: data\n");
            s.push_str(&format!("              mountPath: {}\n", quoted(&o.mount)));
        }
        s.push_str("      volumes:\n        - name: data\n          persistentVolumeClaim:\n");
        s.push_str(&format!("            claimName: {}\n", quoted(&o.claim)));
        s
    }
}

/// A word as Kubernetes reads a command: `$(VAR)` is expanded, so a `$`
/// of text is written `$$`; an engine's expression stays as it is.
fn expanded(word: &Word) -> String {
    match word {
        Word::Text(text) => text.replace('$', "$$"),
        Word::Engine(expression) => expression.clone(),
    }
}

/// A YAML double-quoted scalar: `"` and `\` escaped, and every control or
/// line-breaking character as `\uXXXX`.
fn quoted(value: &str) -> String {
    let mut s = String::from("\"");
    for c in value.chars() {
        match c {
            '"' => s.push_str("\\\""),
            '\\' => s.push_str("\\\\"),
            c if c.is_control() || c == '\u{2028}' || c == '\u{2029}' => {
                s.push_str(&format!("\\u{:04x}", c as u32));
            }
            c => s.push(c),
        }
    }
    s.push('"');
    s
}

/// Longest name accepted: a Job's name is a label (63), and the merge's adds `-merge`.
const MAX_NAME: usize = 63 - "-merge".len();

/// `name` of `option` if it is a DNS label (lower-case letters, digits and
/// `-`, a letter or digit at each end) short enough for `NAME-merge`.
fn label<'a>(option: &'static str, name: &'a str) -> Result<&'a str, JobError> {
    let inner = |c: char| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-';
    let ends = |c: Option<char>| c.is_some_and(|c| c.is_ascii_lowercase() || c.is_ascii_digit());
    if name.len() > MAX_NAME
        || !name.chars().all(inner)
        || !ends(name.chars().next())
        || !ends(name.chars().last())
    {
        return Err(unfit(
            option,
            name,
            "a Job's name is 1 to 57 lower-case letters, digits and `-`, starting and ending with a letter or digit",
        ));
    }
    Ok(name)
}

/// `name` made a DNS label: lower case, each run of other characters a
/// `-`, cut to fit (`glint` if nothing is left).
fn dns_label(name: &str) -> String {
    let mut s = String::new();
    for c in name.chars().map(|c| c.to_ascii_lowercase()) {
        if c.is_ascii_lowercase() || c.is_ascii_digit() {
            s.push(c);
        } else if !s.ends_with('-') {
            s.push('-');
        }
    }
    s.truncate(MAX_NAME);
    let s = s.trim_matches('-');
    if s.is_empty() {
        "glint".to_string()
    } else {
        s.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::{dns_label, label, quoted};

    #[test]
    fn names_become_dns_labels() {
        assert_eq!(dns_label("glint-My Render_2"), "glint-my-render-2");
        assert_eq!(dns_label("--"), "glint");
        assert_eq!(dns_label(&"a".repeat(100)).len(), 57);
        assert!(label("--name", &dns_label(&format!("x{}", "-".repeat(60)))).is_ok());
        assert!(label("--name", "Upper").is_err());
        assert!(label("--name", "-dash").is_err());
        assert!(label("--name", "").is_err());
    }

    #[test]
    fn quoted_escapes_what_yaml_reads_specially() {
        assert_eq!(quoted(r#"a "b" \c"#), r#""a \"b\" \\c""#);
        assert_eq!(quoted("x\ny\u{2028}"), r#""x\u000ay\u2028""#);
    }
}
