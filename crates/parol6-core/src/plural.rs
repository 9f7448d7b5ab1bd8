//! Counted nouns in what the window and the command line print: "1 solution", "2 solutions",
//! "3 stretches" (never "solution(s)"). English's regular plurals only: every noun counted in
//! the program's messages is one.

/// `n` and `noun`, the noun in the plural unless `n` is 1: `count(1, "error")` is "1 error",
/// `count(2, "branch")` is "2 branches" (a noun ending in s, x, z, ch or sh takes "es").
pub fn count(n: usize, noun: &str) -> String {
    if n == 1 {
        return format!("1 {noun}");
    }
    let es = ["s", "x", "z", "ch", "sh"].iter().any(|end| noun.ends_with(end));
    format!("{n} {noun}{}", if es { "es" } else { "s" })
}

#[cfg(test)]
mod tests {
    use super::count;

    #[test]
    fn one_is_singular_and_every_other_count_plural() {
        assert_eq!(count(1, "solution"), "1 solution");
        assert_eq!(count(2, "solution"), "2 solutions");
        assert_eq!(count(0, "warning"), "0 warnings");
        assert_eq!(count(3, "stretch"), "3 stretches");
        assert_eq!(count(2, "branch"), "2 branches");
        assert_eq!(count(1, "branch"), "1 branch");
        assert_eq!(count(7, "cycle"), "7 cycles");
    }
}
