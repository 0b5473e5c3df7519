// k8s_check.mjs -- checks what ties deploy/k8s/*.yaml to the daemon.
//
// usage: node k8s_check.mjs DOCS.json   (all YAML documents as one JSON
// array, made by tests/deploy/run). Checks that the Deployment's probes use
// /readyz (readiness) and /healthz (liveness) on the port the container's
// --port flag names, that terminationGracePeriodSeconds covers the preStop
// pause plus --drain plus --grace, that the selectors of the Deployment, Service and
// PodDisruptionBudget match the pod labels, that the Service targets the
// container port and that the autoscaler scales the Deployment. Prints the
// container's args, one per line, for the caller to start the daemon with;
// exits 1 with one reason per line on stderr when something does not match.
import fs from 'node:fs';

const docs = JSON.parse(fs.readFileSync(process.argv[2], 'utf8'));
const why = [];
const need = (cond, msg) => { if (!cond) why.push(msg); };
const one = (kind) => {
  const found = docs.filter((d) => d && d.kind === kind);
  need(found.length === 1, `expected one ${kind}, found ${found.length}`);
  return found[0] || {};
};
for (const d of docs)  // a Kustomization is kustomize's, not the cluster's
  need(d && d.apiVersion && d.kind &&
       (d.kind === 'Kustomization' || (d.metadata && d.metadata.name)),
       `a document lacks apiVersion, kind or metadata.name`);
const dep = one('Deployment');
const svc = one('Service');
const hpa = one('HorizontalPodAutoscaler');
const pdb = one('PodDisruptionBudget');

const tpl = dep.spec?.template ?? {};
const labels = tpl.metadata?.labels ?? {};
const c = tpl.spec?.containers?.[0] ?? {};
const args = (c.args ?? []).map(String);
const flag = (name) => {
  for (let i = 0; i < args.length; i++) {
    if (args[i] === `--${name}`) return args[i + 1];
    if (args[i].startsWith(`--${name}=`)) return args[i].slice(name.length + 3);
  }
  return undefined;
};
const port = Number(flag('port') ?? 8080); // the daemon's default
const ports = c.ports ?? [];
const resolve = (p) => (typeof p === 'number' ? p
  : /^\d+$/.test(String(p)) ? Number(p)
  : ports.find((q) => q.name === p)?.containerPort);

need(ports.some((p) => p.containerPort === port),
     `no containerPort equals --port ${port}`);
need(flag('bind') === '0.0.0.0' || flag('bind') === '::',
     `--bind must listen on all addresses in a pod, not ${flag('bind')}`);
for (const [probe, path] of [['readinessProbe', '/readyz'],
                             ['livenessProbe', '/healthz']]) {
  const g = c[probe]?.httpGet;
  need(g, `${probe} is not an httpGet probe`);
  if (!g) continue;
  need(g.path === path, `${probe} path ${g.path}, expected ${path}`);
  need(resolve(g.port) === port,
       `${probe} port ${g.port} is not the --port ${port}`);
}
const grace = Number(flag('grace') ?? 10);
const pre = c.lifecycle?.preStop;
let pause = 0;
if (pre?.sleep) pause = Number(pre.sleep.seconds);
else if (pre?.exec?.command?.some((w) => /sleep$/.test(w)))
  pause = Number(pre.exec.command[pre.exec.command.length - 1]);
const drain = Number(flag('drain') ?? 5);
const tgps = tpl.spec?.terminationGracePeriodSeconds ?? 30;
need(tgps >= pause + drain + grace,
     `terminationGracePeriodSeconds ${tgps} < preStop ${pause} + --drain ${drain} + --grace ${grace}`);
const matches = (sel) => sel && Object.keys(sel).length > 0 &&
  Object.entries(sel).every(([k, v]) => labels[k] === v);
need(matches(dep.spec?.selector?.matchLabels), 'Deployment selector does not match its pods');
need(matches(svc.spec?.selector), 'Service selector does not match the pods');
need(matches(pdb.spec?.selector?.matchLabels), 'PodDisruptionBudget selector does not match the pods');
need((svc.spec?.ports ?? []).length > 0 &&
     svc.spec.ports.every((p) => resolve(p.targetPort ?? p.port) === port),
     'Service targetPort is not the container port');
const ref = hpa.spec?.scaleTargetRef ?? {};
need(ref.kind === 'Deployment' && ref.name === dep.metadata?.name,
     'HorizontalPodAutoscaler does not target the Deployment');
need(hpa.spec?.minReplicas >= 1 && hpa.spec?.maxReplicas >= hpa.spec?.minReplicas,
     'HorizontalPodAutoscaler replica bounds are wrong');
need(c.resources?.requests?.cpu && c.resources?.requests?.memory,
     'the container has no resource requests (the autoscaler needs the CPU one)');

for (const a of args) console.log(a);
if (why.length) {
  console.error(why.join('\n'));
  process.exit(1);
}
