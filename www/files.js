// @ts-check
// The chores every part of the page shares, the player's, the camera
// panel's and the workers': a thrown value's message, a URL's response (or
// an error naming the URL), a text saved as a file. Nothing here runs on
// import, so a worker may import it too.

/** A thrown value's message. @param {unknown} e */
export const messageOf = (e) => String(e instanceof Error ? e.message : e);

/**
 * The response to `url`; an error naming the URL and the HTTP status when
 * it is not a success.
 * @param {string} url
 */
export async function fetchOk(url) {
  const response = await fetch(url);
  if (!response.ok) throw new Error(`${url}: HTTP ${response.status} ${response.statusText}`.trimEnd());
  return response;
}

/** Downloads `text` as a file named `name` (a page's, not a worker's). @param {string} text @param {string} name */
export function download(text, name) {
  const a = document.createElement("a");
  a.href = URL.createObjectURL(new Blob([text], { type: "text/plain" }));
  a.download = name;
  a.click();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}
