//! Names as messages show them: a URL's user and password, and the values
//! of its query (signed URLs carry their signature there), hidden. Every
//! line that names a streamed file goes through [`shown`]; [`super::CopcError`]
//! applies it to its name and reason, so an error text from the HTTP
//! client that quotes the URL is covered too.

/// `text` with every `scheme://user:password@host` made `scheme://***@host`
/// and every `?key=value&…` of such a URL made `?key=***&…`.
pub fn shown(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(at) = rest.find("://") {
        let (before, after) = rest.split_at(at + 3);
        out.push_str(before);
        let url_end =
            after.find(|c: char| c.is_whitespace() || matches!(c, '"' | '\'' | '<' | '>')).unwrap_or(after.len());
        let (url, tail) = after.split_at(url_end);
        let authority_end = url.find(['/', '?', '#']).unwrap_or(url.len());
        let (authority, path) = url.split_at(authority_end);
        match authority.rfind('@') {
            Some(a) => {
                out.push_str("***");
                out.push_str(&authority[a..]);
            }
            None => out.push_str(authority),
        }
        match path.find('?') {
            Some(q) => {
                out.push_str(&path[..=q]);
                let (query, fragment) = path[q + 1..].split_at(path[q + 1..].find('#').unwrap_or(path.len() - q - 1));
                let hidden: Vec<String> = query
                    .split('&')
                    .map(|pair| match pair.split_once('=') {
                        Some((key, _)) => format!("{key}=***"),
                        None => pair.to_string(),
                    })
                    .collect();
                out.push_str(&hidden.join("&"));
                out.push_str(fragment);
            }
            None => out.push_str(path),
        }
        rest = tail;
    }
    out.push_str(rest);
    out
}

/// The URL with its user and password taken out (query kept): what
/// identifies the file for caches, never shown.
pub fn without_credentials(url: &str) -> String {
    let Some(at) = url.find("://") else { return url.to_string() };
    let start = at + 3;
    let authority_end = url[start..].find(['/', '?', '#']).map_or(url.len(), |e| start + e);
    match url[start..authority_end].rfind('@') {
        Some(a) => format!("{}{}", &url[..start], &url[start + a + 1..]),
        None => url.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn credentials_and_query_values_are_hidden() {
        assert_eq!(shown("http://user:s3cretpw@127.0.0.1:8080/x.copc.laz"), "http://***@127.0.0.1:8080/x.copc.laz");
        assert_eq!(
            shown("error: https://h/a.copc.laz?X-Amz-Signature=abc&X-Amz-Expires=60#f: HTTP 403"),
            "error: https://h/a.copc.laz?X-Amz-Signature=***&X-Amz-Expires=***#f: HTTP 403"
        );
        assert_eq!(shown("bad uri: http://u:p@/x is missing host"), "bad uri: http://***@/x is missing host");
        assert_eq!(shown("/data/a@b.copc.laz"), "/data/a@b.copc.laz");
        assert_eq!(shown("http://h/p@q"), "http://h/p@q", "an @ in the path is no user");
        assert_eq!(shown("a http://u:p@h/ and https://v:q@k/x"), "a http://***@h/ and https://***@k/x");
        assert_eq!(without_credentials("http://u:p@h:1/x?k=v"), "http://h:1/x?k=v");
        assert_eq!(without_credentials("/local/file.copc.laz"), "/local/file.copc.laz");
    }
}
