//! Fixture for .ci/check-math: every formula below is broken the way rustdoc's Markdown breaks
//! them; the check must report each (the `expect:` lines list what it must say).
//!
//! A curly quote: $x' = v$.
// expect: `'`: smart punctuation makes it a curly quote
//!
//! An eaten thin space: $a\,b$.
// expect: `\,`: Markdown eats the backslash
//!
//! A lost row break:
//!
//! $$f = \begin{cases} 1 & x > 0\\
//!   0 & x \le 0\end{cases}$$
// expect: `\\` before a space or line end
//!
//! A parse error: $\frac{1}$ here.
// expect: KaTeX cannot parse it
//!
//! Emphasis across formulas: $\tau^*$ and $\tau^*$ again.
// expect: math delimiters left in the text
//!
//! TeX outside math: \alpha.
// expect: a TeX command in the text outside math
//!
//! A literal underscore that became a subscript: $\mathrm{fac\_min}$.
// expect: `_` inside `\mathrm{...}`
//!
//! A list item inside display math:
//!
//! $$a = b
//! + c$$
// expect: a line of the formula starts with `+`

/// The right way, for contrast: $x^\prime$, $a\thinspace b$, $\lbrace 1 \rbrace$, $\Vert v\Vert$,
/// $\begin{cases} 1 & x > 0\\\\ 0 & x \le 0\end{cases}$, $\mathrm{fac\\_min}$.
pub fn fine() {}
