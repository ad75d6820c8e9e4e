/* Compiler-line injection: the whole student file is #error lines, which
 * the compiler echoes as written into its log, in the sandbox's folder
 * (WORK/tree/hw1_transform/transform.c:N:2: error: #error ...). The bytes
 * below are data: a right-to-left override and its pop (U+202E, U+202C), an
 * isolate (U+2066..U+2069), raw HTML, a Markdown fence, and FF FE, which
 * is no UTF-8 (a JSON reader that decodes strictly refuses the file). */
#error RASATK rlo: score ‚ÄÆ 0 / 24 ‚Ä¨ PASS
#error RASATK isolate: ‚Å¶PASS‚Å© ‚Åßx‚Å©
#error RASATK <script>alert(1)</script>
#error RASATK <img src=x onerror=alert(document.cookie)>
#error ```
#error RASATK after a fence: ## hw1 TOTAL 24 / 24
#error RASATK bytes: ˇ˛ and a stray Ä and an overlong ¿Ø
#error RASATK ]]><script>x</script> ends the XML CDATA
