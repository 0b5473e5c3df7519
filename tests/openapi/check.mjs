// check.mjs -- lints openapi.yaml and validates saved responses against it.
//
//   node check.mjs openapi.yaml api/api.h RESPONSES_DIR
//
// A saved response is a JSON file written by the integration tests:
// {"method": "POST", "path": "/voronoi", "status": 200,
//  "content_type": "application/json", "headers": {...}, "body": "<text>"}
// (body is the decoded text; a body that is not UTF-8 is "body_hex").
// Each is matched to its operation (method, path template), its response
// (status, or the shared component response for 404/405 on any path) and
// its media type; JSON bodies are validated with ajv (draft 2020-12).
// Prints one line per failure and "N passed, M failed".
import fs from "node:fs";
import path from "node:path";
import YAML from "yaml";
import Ajv2020 from "ajv/dist/2020.js";
import addFormats from "ajv-formats";
import { Validator } from "@seriousme/openapi-schema-validator";

const [specFile, apiHeader, respDir] = process.argv.slice(2);
let passed = 0;
let failed = 0;
const fail = (what, msg) => {
  failed++;
  console.log(`FAIL ${what}: ${msg}`);
};
const pass = () => passed++;

// ---- 1. the document against the OpenAPI 3.1 schema ----------------------
const text = fs.readFileSync(specFile, "utf8");
const spec = YAML.parse(text);
const validator = new Validator();
const res = await validator.validate(spec);
if (!res.valid) fail("openapi.yaml", JSON.stringify(res.errors, null, 1));
else if (validator.version !== "3.1") fail("openapi.yaml", `version ${validator.version}, expected 3.1`);
else pass();
try {
  validator.resolveRefs();
  pass();
} catch (e) {
  fail("openapi.yaml $refs", e.message);
}

// Every $ref points at something.
const resolvePointer = (ref) => {
  if (!ref.startsWith("#/")) throw new Error(`external $ref ${ref}`);
  let node = spec;
  for (const raw of ref.slice(2).split("/")) {
    const key = raw.replace(/~1/g, "/").replace(/~0/g, "~");
    if (node === undefined || !(key in node)) throw new Error(`dangling $ref ${ref}`);
    node = node[key];
  }
  return node;
};
const walk = (node, fn) => {
  if (Array.isArray(node)) node.forEach((n) => walk(n, fn));
  else if (node && typeof node === "object") {
    fn(node);
    Object.values(node).forEach((n) => walk(n, fn));
  }
};
let refErrors = 0;
walk(spec, (n) => {
  if (typeof n.$ref === "string") {
    try {
      resolvePointer(n.$ref);
    } catch (e) {
      refErrors++;
      fail("openapi.yaml", e.message);
    }
  }
});
if (refErrors === 0) pass();

// ---- 2. component schemas compile under JSON Schema 2020-12 ---------------
const ajv = new Ajv2020({ strict: true, allErrors: true, strictTypes: false });
addFormats(ajv);
ajv.addFormat("binary", true);
for (const kw of ["example", "discriminator", "xml", "externalDocs"]) ajv.addKeyword(kw);
// The component schemas become $defs of one schema, their $refs rewritten.
const defs = JSON.parse(
  JSON.stringify(spec.components.schemas).replaceAll('"#/components/schemas/', '"#/$defs/'),
);
ajv.addSchema({ $id: "openapi", $defs: defs });
const schemaRef = (ref) => ({ $ref: ref.replace("#/components/schemas/", "openapi#/$defs/") });
for (const name of Object.keys(spec.components.schemas)) {
  try {
    ajv.compile(schemaRef(`#/components/schemas/${name}`));
    pass();
  } catch (e) {
    fail(`schema ${name}`, e.message);
  }
}

// Operations: unique ids, every error response is problem+json.
const methods = ["get", "put", "post", "delete", "options", "head", "patch", "trace"];
const ops = [];
for (const [p, item] of Object.entries(spec.paths)) {
  for (const m of methods) if (item[m]) ops.push({ path: p, method: m, op: item[m] });
}
const ids = new Set();
for (const { path: p, method: m, op } of ops) {
  const what = `${m.toUpperCase()} ${p}`;
  if (!op.operationId || ids.has(op.operationId)) fail(what, "missing or duplicate operationId");
  ids.add(op.operationId);
  for (const [status, r0] of Object.entries(op.responses || {})) {
    const r = r0.$ref ? resolvePointer(r0.$ref) : r0;
    if (Number(status) >= 400 && !(r.content && r.content["application/problem+json"]))
      fail(what, `${status} is not application/problem+json`);
  }
  pass();
}

// The problem types are exactly those of api/api.h's table.
const header = fs.readFileSync(apiHeader, "utf8");
const slugs = [...header.matchAll(/X\(API_[A-Z_]+,\s*"([a-z-]+)",\s*(\d+)/g)]
  .filter((m) => m[1] !== "ok")
  .map((m) => `/problems/${m[1]}`)
  .sort();
const enumTypes = [...spec.components.schemas.Problem.properties.type.enum].sort();
if (JSON.stringify(slugs) !== JSON.stringify(enumTypes))
  fail("Problem.type", `api.h has ${slugs.join(" ")}; openapi.yaml has ${enumTypes.join(" ")}`);
else pass();

// ---- 3. saved responses ----------------------------------------------------
const templates = Object.keys(spec.paths).map((p) => ({
  p,
  re: new RegExp("^" + p.replace(/\{[^/]+\}/g, "[^/]+") + "$"),
  literal: !p.includes("{"),
}));
const findPath = (urlPath) =>
  templates.find((t) => t.literal && t.p === urlPath) || templates.find((t) => !t.literal && t.re.test(urlPath));
const sharedByStatus = { 404: "NotFound", 413: "TooLarge", 503: "Unavailable" };
// 405 has no operation to belong to (it answers the methods a path does
// not offer); the contract describes it in info.description: a problem
// with Allow.
const methodNotAllowed = {
  headers: { Allow: spec.components.headers.Allow },
  content: { "application/problem+json": { schema: { $ref: "#/components/schemas/Problem" } } },
};

const files = respDir && fs.existsSync(respDir)
  ? fs.readdirSync(respDir).filter((f) => f.endsWith(".json")).sort()
  : [];
if (files.length === 0) fail("responses", `no saved responses in ${respDir}`);
const covered = new Set();
const validators = new Map();
for (const f of files) {
  const what = `response ${f}`;
  let r;
  try {
    r = JSON.parse(fs.readFileSync(path.join(respDir, f), "utf8"));
  } catch (e) {
    fail(what, `unreadable: ${e.message}`);
    continue;
  }
  const method = r.method.toLowerCase() === "head" ? "get" : r.method.toLowerCase();
  const t = findPath(r.path);
  const op = t && spec.paths[t.p][method];
  let resp;
  if (op && op.responses[String(r.status)]) {
    resp = op.responses[String(r.status)];
    covered.add(`${method} ${t.p}`);
  } else if (sharedByStatus[r.status]) {
    resp = spec.components.responses[sharedByStatus[r.status]];
  } else if (r.status === 405) {
    resp = methodNotAllowed;
  } else {
    fail(what, `${r.method} ${r.path} ${r.status} is not in the contract`);
    continue;
  }
  if (resp.$ref) resp = resolvePointer(resp.$ref);
  for (const [h, def] of Object.entries(resp.headers || {})) {
    // Headers the contract promises on every such answer.
    if (["Allow", "Retry-After"].includes(h) && !(h.toLowerCase() in (r.headers || {})))
      fail(what, `header ${h} missing`);
    void def;
  }
  if (!resp.content) {
    if (r.body && r.body.length > 0) fail(what, "body where the contract has none");
    else pass();
    continue;
  }
  const mediaType = (r.content_type || "").split(";")[0].trim().toLowerCase();
  const media = resp.content[mediaType];
  if (!media) {
    fail(what, `content type ${mediaType} not declared for ${r.status} (declared: ${Object.keys(resp.content).join(", ")})`);
    continue;
  }
  if (/json$/.test(mediaType)) {
    let body;
    try {
      body = JSON.parse(r.body);
    } catch (e) {
      fail(what, `body is not JSON: ${e.message}`);
      continue;
    }
    const key = JSON.stringify(media.schema);
    if (!validators.has(key)) {
      const ref = media.schema.$ref ? schemaRef(media.schema.$ref) : media.schema;
      validators.set(key, ajv.compile(ref));
    }
    const v = validators.get(key);
    if (!v(body)) {
      fail(what, ajv.errorsText(v.errors, { separator: "; " }).slice(0, 600));
      continue;
    }
  } else if (typeof r.body !== "string" && typeof r.body_hex !== "string") {
    fail(what, "no body saved");
    continue;
  }
  pass();
}

// Every operation of the contract was seen answering at least once.
for (const { path: p, method: m } of ops) {
  if (m === "head") continue;
  if (!covered.has(`${m} ${p}`)) fail(`${m.toUpperCase()} ${p}`, "no saved response exercised it");
}

console.log(`openapi: ${files.length} saved responses checked`);
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed === 0 ? 0 : 1);
