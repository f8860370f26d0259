//! Regression: the README's `cargo run -p sphere_bench` command failed ("could not determine
//! which binary to run") once the package had two binaries. Every such command in the README
//! must name a binary or rely on the package's `default-run`, and that binary must exist.

use std::path::Path;

#[test]
fn readme_bench_commands_name_a_binary_that_exists() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("../../README.md")).unwrap();
    let manifest = std::fs::read_to_string(root.join("Cargo.toml")).unwrap();
    let default_run = manifest
        .lines()
        .find_map(|l| l.strip_prefix("default-run = "))
        .map(|v| v.trim_matches('"').to_owned());
    let bins: Vec<String> = manifest
        .split("[[bin]]")
        .skip(1)
        .filter_map(|section| {
            section
                .lines()
                .find_map(|l| l.strip_prefix("name = "))
                .map(|v| v.trim_matches('"').to_owned())
        })
        .collect();
    let commands: Vec<&str> = readme
        .lines()
        .map(str::trim)
        .filter(|l| l.starts_with("cargo run") && l.contains("-p sphere_bench"))
        .collect();
    assert!(!commands.is_empty());
    for command in commands {
        let words: Vec<&str> = command.split_whitespace().collect();
        let named = words
            .iter()
            .position(|w| *w == "--bin")
            .map(|i| words[i + 1].to_owned());
        let bin = named
            .or_else(|| default_run.clone())
            .unwrap_or_else(|| panic!("{command:?} names no binary and there is no default-run"));
        assert!(
            bins.contains(&bin),
            "{command:?} runs {bin}, not one of {bins:?}"
        );
    }
}
