//! A parser of `aapt dump xmltree` output: the compiled manifest as a tree of elements.

/// One element of `aapt dump xmltree` output.
#[derive(Debug, Default)]
pub struct XmlElement {
    /// Tag name.
    pub name: String,
    /// (attribute name without namespace prefix or resource id, value as printed: strings
    /// unquoted, others like `(type 0x12)0x0`).
    pub attrs: Vec<(String, String)>,
    /// Child elements.
    pub children: Vec<XmlElement>,
}

impl XmlElement {
    /// An attribute's value.
    pub fn attr(&self, name: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_str())
    }

    /// Children named `name`.
    pub fn kids<'a>(&'a self, name: &'a str) -> impl Iterator<Item = &'a XmlElement> + 'a {
        self.children.iter().filter(move |c| c.name == name)
    }

    /// The first child `name` whose `android:name` is `value`.
    pub fn named(&self, name: &str, value: &str) -> Option<&XmlElement> {
        self.children
            .iter()
            .find(|c| c.name == name && c.attr("name") == Some(value))
    }
}

/// Parses `aapt dump xmltree` output into its root element.
pub fn parse_xmltree(text: &str) -> Option<XmlElement> {
    // Stack of (indent, element) for open elements.
    let mut stack: Vec<(usize, XmlElement)> = Vec::new();
    let close_to = |stack: &mut Vec<(usize, XmlElement)>, indent: usize| {
        while stack.len() > 1 && stack.last().is_some_and(|(i, _)| *i >= indent) {
            let (_, done) = stack.pop().expect("non-empty");
            stack.last_mut().expect("parent").1.children.push(done);
        }
    };
    for line in text.lines() {
        let indent = line.len() - line.trim_start().len();
        let body = line.trim_start();
        if let Some(rest) = body.strip_prefix("E: ") {
            let name = rest.split_whitespace().next()?.to_string();
            close_to(&mut stack, indent);
            if stack.len() == 1 && stack[0].0 >= indent {
                return None; // a second root
            }
            stack.push((
                indent,
                XmlElement {
                    name,
                    ..XmlElement::default()
                },
            ));
        } else if let Some(rest) = body.strip_prefix("A: ") {
            close_to(&mut stack, indent);
            let (key, value) = rest.split_once('=')?;
            let key = key.split('(').next()?.trim();
            let key = key.rsplit(':').next()?.to_string();
            let value = match value.strip_prefix('"') {
                Some(v) => v.split('"').next()?.to_string(),
                None => value.trim().to_string(),
            };
            stack.last_mut()?.1.attrs.push((key, value));
        }
    }
    close_to(&mut stack, 0);
    stack.pop().map(|(_, e)| e)
}
