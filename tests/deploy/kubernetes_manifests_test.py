#!/usr/bin/env python3
"""Checks deploy/kubernetes and deploy/Dockerfile against what incise-server really reads, so that
they cannot drift apart (docs/scale_out.md):

    python3 tests/deploy/kubernetes_manifests_test.py --server build/bin/incise-server --repo .
        [--kubectl kubectl]

It renders the manifests with `kubectl kustomize`, takes the server's flags from its --help and
the environment variables it reads from its sources (std::getenv), then starts the real server
with the Deployment's arguments and asks it the probes' paths. One line on stderr per failure;
exit 1 if there was any. Needs python3-yaml (Debian's package).
"""
import argparse
import base64
import glob
import json
import os
import queue
import re
import signal
import subprocess
import sys
import tempfile
import threading
import time
import urllib.parse
import urllib.request

import yaml

failures = []

# What the downward API would give a pod, for starting the server here.
SAMPLE_FIELDS = {"metadata.name": "incise-server-5d8c7b9f4-x2x7q", "status.podIP": "127.0.0.1"}
# What a node in a cluster must be given, and from where.
REQUIRED_ENV = {"INCISE_DATABASE_URL": "secret", "INCISE_NODE_ID": "field:metadata.name",
                "INCISE_NODE_ADDRESS": "value"}
VARIABLE = re.compile(r"\$\(([A-Za-z_][A-Za-z0-9_]*)\)")


def check(ok, message):
    if not ok:
        failures.append(message)
        print(f"kubernetes_manifests_test: FAIL: {message}", file=sys.stderr)
    return ok


class Fatal(Exception):
    """Nothing further can be checked."""


# What the repository says.

def render(kubectl, folder):
    run = subprocess.run([kubectl, "kustomize", folder], capture_output=True, text=True)
    if run.returncode != 0:
        raise Fatal(f"`{kubectl} kustomize {folder}` failed: {run.stderr.strip()}")
    return [d for d in yaml.safe_load_all(run.stdout) if d]


def find(docs, kind, name):
    for d in docs:
        if d.get("kind") == kind and d["metadata"]["name"] == name:
            return d
    raise Fatal(f"the rendered manifests have no {kind} {name}")


def server_flags(server):
    run = subprocess.run([server, "--help"], capture_output=True, text=True, timeout=30)
    if run.returncode != 0:
        raise Fatal(f"`{server} --help` exited {run.returncode}")
    return set(re.findall(r"--[a-z][a-z-]*", run.stdout))


def server_env_names(repo):
    names = set()
    for path in glob.glob(os.path.join(repo, "server", "**", "*.[ch]*"), recursive=True):
        with open(path, encoding="utf-8", errors="replace") as f:
            names.update(re.findall(r'std::getenv\("([A-Za-z0-9_]+)"\)', f.read()))
    if not names:
        raise Fatal(f"no std::getenv(\"...\") found under {repo}/server")
    return names


def server_body_limit(repo):
    path = os.path.join(repo, "server", "app_state.h")
    with open(path, encoding="utf-8") as f:
        m = re.search(r"api_body_limit\s*=\s*(\d+)\s*\*\s*1024", f.read())
    if not m:
        raise Fatal(f"no 'api_body_limit = N * 1024' in {path}: update this test")
    return int(m.group(1)) * 1024


def dockerfile(repo):
    """The final stage's USER, EXPOSE, ENTRYPOINT and CMD (the last two None unless JSON lists)."""
    with open(os.path.join(repo, "deploy", "Dockerfile"), encoding="utf-8") as f:
        text = re.sub(r"\\\n", " ", f.read())
    stage = {}
    for line in text.splitlines():
        word, _, rest = line.strip().partition(" ")
        word = word.upper()
        if word == "FROM":
            stage = {}
        elif word in ("ENTRYPOINT", "CMD"):
            try:
                stage[word] = json.loads(rest)
            except json.JSONDecodeError:
                stage[word] = None
        elif word in ("USER", "EXPOSE"):
            stage[word] = rest.strip()
    return stage


# Reading a pod the way Kubernetes does.

def value_of(args, flag):
    return args[args.index(flag) + 1] if flag in args[:-1] else None


def port_number(port, container):
    """A probe's or Service's port (a number or a port's name) as the container's port number."""
    if isinstance(port, int):
        return port
    return next((p["containerPort"] for p in container.get("ports", [])
                 if p.get("name") == port), None)


def data_of(docs, kind, name):
    found = [d for d in docs if d["kind"] == kind and d["metadata"]["name"] == name]
    if not found:
        return None
    data = found[0].get("data") or {}
    if kind == "Secret":
        return {k: base64.b64decode(v).decode() for k, v in data.items()}
    return dict(data)


def expand(text, env, where):
    """Kubernetes' $(VAR) expansion. It leaves a name not defined before as it is: a mistake."""
    def one(m):
        if check(m.group(1) in env, f"{where}: $({m.group(1)}) names no variable defined before"):
            return env[m.group(1)][1]
        return m.group(0)
    return VARIABLE.sub(one, text)


def resolve_env(container, docs, where):
    """name -> (source, value). The source is "value", "field:PATH", "configmap" or "secret"; the
    value is plain text, with fields as SAMPLE_FIELDS and $(VAR) expanded."""
    env = {}
    for e in container.get("envFrom", []):
        for kind, ref_key in (("ConfigMap", "configMapRef"), ("Secret", "secretRef")):
            if ref_key in e:
                data = data_of(docs, kind, e[ref_key]["name"])
                check(data is not None, f"{where} envFrom: no {kind} {e[ref_key]['name']}")
                for key, value in (data or {}).items():
                    env[e.get("prefix", "") + key] = (kind.lower(), value)
    for e in container.get("env", []):
        name, source = e["name"], e.get("valueFrom", {})
        if "value" in e:
            env[name] = ("value", expand(str(e["value"]), env, f"{where} env {name}"))
        elif "fieldRef" in source:
            path = source["fieldRef"]["fieldPath"]
            env[name] = (f"field:{path}", SAMPLE_FIELDS.get(path, path))
        for kind, ref_key in (("ConfigMap", "configMapKeyRef"), ("Secret", "secretKeyRef")):
            if ref_key in source:
                ref = source[ref_key]
                value = (data_of(docs, kind, ref["name"]) or {}).get(ref["key"])
                check(value is not None, f"{where} env {name}: {ref_key} "
                      f"{ref['name']}/{ref['key']} is not in the rendered {kind}s")
                env[name] = (kind.lower(), value or "")
    return env


# The checks.

def check_env(container, env, repo):
    """Every INCISE_ variable is one the server reads; the ones a node needs are there."""
    read = server_env_names(repo)
    for name in env:
        check(not name.startswith("INCISE_") or name in read,
              f"env {name} is set, but the server never reads it (std::getenv in server/)")
    for name, source in REQUIRED_ENV.items():
        check(env.get(name, ("missing",))[0] == source,
              f"env {name} must come from {source}, not {env.get(name, ('missing',))[0]}")
    raw = next((e.get("value", "") for e in container.get("env", [])
                if e["name"] == "INCISE_NODE_ADDRESS"), "")
    address = re.fullmatch(r"\$\((\w+)\):(\d+)", raw)
    if not check(address, f"env INCISE_NODE_ADDRESS {raw!r} must be $(POD_IP_VARIABLE):PORT"):
        return None
    check(env.get(address.group(1), ("",))[0] == "field:status.podIP",
          f"INCISE_NODE_ADDRESS's $({address.group(1)}) must be the pod's IP (status.podIP)")
    return int(address.group(2))


def container_args(container, env, flags):
    """The arguments as Kubernetes expands them, and those to run here (without what comes from a
    Secret); each flag is one of the server's."""
    args, plain = [], []
    for raw in [str(a) for a in container.get("command", [])[1:] + container.get("args", [])]:
        args.append(expand(raw, env, "Deployment args"))
        secret = [v for v in VARIABLE.findall(raw) if env.get(v, ("",))[0] == "secret"]
        if check(not secret, f"argument $({secret and secret[0]}) comes from a Secret: anyone on "
                             f"the node could read it in ps"):
            plain.append(args[-1])
        elif plain and plain[-1].startswith("--"):
            plain.pop()
    for a in args:
        check(not a.startswith("--") or a in flags,
              f"Deployment argument {a} is not an incise-server flag")
    return args, plain


def check_security(pod, container, args, user):
    """Not root, as the image's user; a read-only root with the data folder on a volume."""
    check(user.isdigit() and int(user) != 0, f"deploy/Dockerfile USER {user!r} must be a numeric "
          f"uid other than 0 (runAsNonRoot can check only a number)")
    context = {**pod.get("securityContext", {}), **container.get("securityContext", {})}
    check(context.get("runAsNonRoot") is True, "the server's pod must set runAsNonRoot: true")
    check(str(context.get("runAsUser")) == user,
          f"runAsUser {context.get('runAsUser')} is not the Dockerfile's USER {user}")
    volumes = {v["name"] for v in pod.get("volumes", [])}
    mounts = container.get("volumeMounts", [])
    for m in mounts:
        check(m["name"] in volumes, f"volumeMount {m['name']} names no volume of the pod")
    data = value_of(args, "--data") or ""
    if context.get("readOnlyRootFilesystem"):
        check(any((data + "/").startswith(m["mountPath"].rstrip("/") + "/") for m in mounts),
              f"the root filesystem is read-only, but --data {data} is on no mounted volume")


def check_image(image, args, port, flags):
    """The image's defaults agree with the Deployment."""
    entry = image.get("ENTRYPOINT") or [""]
    check(os.path.basename(entry[0]) == "incise-server",
          f"deploy/Dockerfile ENTRYPOINT {image.get('ENTRYPOINT')} must be [\"incise-server\"]")
    cmd = image.get("CMD") or []
    check(cmd, "deploy/Dockerfile CMD must be a JSON list of arguments")
    for a in cmd:
        check(not a.startswith("--") or a in flags,
              f"Dockerfile CMD argument {a} is not an incise-server flag")
    check(image.get("EXPOSE") == str(port),
          f"Dockerfile EXPOSE {image.get('EXPOSE')} is not the containerPort {port}")
    for flag in ("--port", "--web", "--data"):
        check(value_of(cmd, flag) == value_of(args, flag), f"{flag}: the Dockerfile's CMD says "
              f"{value_of(cmd, flag)}, the Deployment {value_of(args, flag)}")


def check_service(service, container, labels):
    name = f"Service {service['metadata']['name']}"
    selector = service["spec"].get("selector", {})
    check(selector and all(labels.get(k) == v for k, v in selector.items()),
          f"{name}: selector {selector} does not match the pods' labels {labels}")
    for p in service["spec"]["ports"]:
        target = p.get("targetPort", p["port"])
        check(port_number(target, container) in [c["containerPort"] for c in container["ports"]],
              f"{name}: targetPort {target} is not a port of container {container['name']}")


def size_bytes(text):
    m = re.fullmatch(r"(\d+)([kKmMgG]?)", str(text).strip())
    unit = {"": 1, "k": 1 << 10, "m": 1 << 20, "g": 1 << 30}
    return int(m.group(1)) * unit[m.group(2).lower()] if m else None


def check_ingress(ingress, service, body_limit):
    name = f"Ingress {ingress['metadata']['name']}"
    notes = ingress["metadata"].get("annotations", {})
    for key in ("proxy-read-timeout", "proxy-send-timeout"):
        value = notes.get(f"nginx.ingress.kubernetes.io/{key}", "60")
        check(value.isdigit() and int(value) >= 3600,
              f"{name}: {key} {value} s would cut a live session's WebSockets (want >= 3600)")
    size = size_bytes(notes.get("nginx.ingress.kubernetes.io/proxy-body-size", "1m"))
    check(size is not None and (size == 0 or size >= body_limit),
          f"{name}: proxy-body-size {size} B is below the server's body limit {body_limit} B")
    tls = ingress["spec"].get("tls", [])
    check(tls and all(t.get("secretName") for t in tls),
          f"{name}: TLS ends here, so it needs a tls entry with a secretName")
    ports = [p.get("name") for p in service["spec"]["ports"]] + \
            [p["port"] for p in service["spec"]["ports"]]
    backends = [path["backend"] for rule in ingress["spec"].get("rules", [])
                for path in rule.get("http", {}).get("paths", [])]
    check(backends, f"{name} has no backend")
    for backend in backends:
        target = backend.get("service", {})
        port = target.get("port", {})
        check(target.get("name") == "incise-server",
              f"{name}: backend {target.get('name')} is not the Service incise-server")
        check(port.get("name", port.get("number")) in ports,
              f"{name}: backend port {port} is not a port of Service incise-server")


def check_postgres(docs, url):
    """PostgreSQL is where INCISE_DATABASE_URL says, with the same user, password and database."""
    database = find(docs, "StatefulSet", "incise-postgres")
    container = database["spec"]["template"]["spec"]["containers"][0]
    env = resolve_env(container, docs, "StatefulSet incise-postgres")
    service = find(docs, "Service", database["spec"]["serviceName"])
    name = service["metadata"]["name"]
    check(service["spec"].get("clusterIP") == "None", f"Service {name} must be headless")
    check_service(service, container, database["spec"]["template"]["metadata"]["labels"])
    check(database["spec"].get("volumeClaimTemplates"), "PostgreSQL needs a volumeClaimTemplate")
    ready = container.get("readinessProbe", {}).get("exec", {}).get("command", [])
    check("pg_isready" in ready, "PostgreSQL's readinessProbe must run pg_isready")
    if not url:
        return  # already reported
    parts = urllib.parse.urlsplit(url)
    check(parts.hostname == name and parts.port in [p["port"] for p in service["spec"]["ports"]],
          f"INCISE_DATABASE_URL's {parts.hostname}:{parts.port} is not Service {name}'s name "
          f"and port")
    for part, key in ((parts.username, "POSTGRES_USER"), (parts.password, "POSTGRES_PASSWORD"),
                      (parts.path.lstrip("/"), "POSTGRES_DB")):
        check(urllib.parse.unquote(part or "") == env.get(key, ("", None))[1],
              f"INCISE_DATABASE_URL and PostgreSQL's {key} differ")


# The real server.

def run_server(server, args, env, probes, grace_s):
    """Starts the real server as a pod would, but on a free local port with SQLite in a temporary
    folder; checks that it takes the node's id and address, answers each probe, and stops within
    grace_s of SIGTERM."""
    with tempfile.TemporaryDirectory() as tmp:
        local = {"--host": "127.0.0.1", "--port": "0", "--data": tmp, "--web": tmp}
        run_args = []
        for a in args:
            flag = run_args[-1] if run_args else None
            run_args.append(local[flag] if flag in local else a)
        for flag in local:
            if flag not in run_args:
                run_args += [flag, local[flag]]
        environment = {k: v for k, v in os.environ.items() if not k.startswith("INCISE_")}
        environment.update({k: v for k, (_, v) in env.items() if k != "INCISE_DATABASE_URL"})
        log = os.path.join(tmp, "stderr")

        def said():  # the server's own lines on stderr
            with open(log, encoding="utf-8", errors="replace") as f:
                return [l for l in f.read().splitlines() if l.startswith("incise-server:")]

        with open(log, "w") as stderr:
            process = subprocess.Popen([server] + run_args, env=environment, text=True,
                                       stdout=subprocess.PIPE, stderr=stderr)
        lines = queue.Queue()
        threading.Thread(target=lambda: [lines.put(l) for l in process.stdout], daemon=True).start()
        try:
            port = None
            deadline = time.monotonic() + 30
            while not port and time.monotonic() < deadline and process.poll() is None:
                try:
                    m = re.search(r"listening on http://[^:]+:(\d+)", lines.get(timeout=0.2))
                    port = m and int(m.group(1))
                except queue.Empty:
                    pass
            # Then it checks INCISE_NODE_ADDRESS and says where the other nodes reach it.
            address = None
            deadline = time.monotonic() + 5
            while port and not address and time.monotonic() < deadline and process.poll() is None:
                found = [re.search(r"other nodes reach this one at (\S+)", l) for l in said()]
                address = next((m.group(1) for m in found if m), None)
                time.sleep(0.05)
            if not port or process.poll() is not None:
                raise Fatal(f"the server did not start with the Deployment's arguments "
                            f"{' '.join(run_args)}: {(said() or ['no message'])[-1]}")
            expected = env.get("INCISE_NODE_ADDRESS", ("", None))[1]
            check(address == expected, f"the server says other nodes reach it at {address}, not "
                  f"at INCISE_NODE_ADDRESS {expected}")
            node = env.get("INCISE_NODE_ID", ("", None))[1]
            for kind, path in probes:
                body = check_probe(port, kind, path)
                check(not body or node is None or body.get("node", node) == node,
                      f"{kind} GET {path} names node {body and body.get('node')}, not "
                      f"INCISE_NODE_ID {node}")
            process.send_signal(signal.SIGTERM)
            start = time.monotonic()
            code = process.wait(timeout=grace_s + 5)
            check(code == 0, f"the server exited {code} on SIGTERM")
            check(time.monotonic() - start <= grace_s,
                  f"the server took {time.monotonic() - start:.1f} s to stop on SIGTERM; the "
                  f"pod gives it {grace_s} s after its preStop hook")
        finally:
            if process.poll() is None:
                process.kill()
                process.wait()


def check_probe(port, kind, path):
    """The probe's answer on the real server, a JSON object, or None after a failure."""
    try:
        with urllib.request.urlopen(f"http://127.0.0.1:{port}{path}", timeout=5) as answer:
            body = json.loads(answer.read())
            if check(isinstance(body, dict), f"{kind} GET {path}: not a JSON object"):
                return body
    except (OSError, ValueError) as e:
        check(False, f"{kind} GET {path} failed on the real server: {e}")
    return None


def check_all(docs, repo, server):
    flags = server_flags(server)
    deployment = find(docs, "Deployment", "incise-server")
    pod = deployment["spec"]["template"]["spec"]
    labels = deployment["spec"]["template"]["metadata"]["labels"]
    container = next((c for c in pod["containers"] if c["name"] == "incise-server"), None)
    if container is None:
        raise Fatal("the Deployment has no container incise-server")
    ports = [p["containerPort"] for p in container.get("ports", [])]
    if len(ports) != 1:
        raise Fatal(f"the incise-server container should have one port, has {ports}")
    port = ports[0]

    env = resolve_env(container, docs, "Deployment")
    node_port = check_env(container, env, repo)
    check(node_port in (None, port),
          f"INCISE_NODE_ADDRESS's port {node_port} is not the containerPort {port}")
    args, plain_args = container_args(container, env, flags)
    check(value_of(args, "--port") == str(port),
          f"--port {value_of(args, '--port')} is not the containerPort {port}")
    probes = []
    for kind in ("readinessProbe", "livenessProbe"):
        get = container.get(kind, {}).get("httpGet")
        if check(get, f"the container has no {kind} with httpGet"):
            check(port_number(get["port"], container) == port,
                  f"{kind} port {get['port']} is not the containerPort {port}")
            probes.append((kind, get["path"]))
    image = dockerfile(repo)
    check_security(pod, container, args, image.get("USER", "").split(":")[0])
    check_image(image, args, port, flags)

    service = find(docs, "Service", "incise-server")
    check_service(service, container, labels)
    nodes = find(docs, "Service", "incise-nodes")
    check(nodes["spec"].get("clusterIP") == "None",
          "Service incise-nodes must be headless (clusterIP: None)")
    check_service(nodes, container, labels)
    check(node_port in [p["port"] for p in nodes["spec"]["ports"]], f"Service incise-nodes has "
          f"no port {node_port}, where the nodes forward (INCISE_NODE_ADDRESS)")
    ingresses = [d for d in docs if d["kind"] == "Ingress"]
    check(ingresses, "the rendered manifests have no Ingress")
    for ingress in ingresses:
        check_ingress(ingress, service, server_body_limit(repo))
    check_postgres(docs, env.get("INCISE_DATABASE_URL", ("", ""))[1])

    grace = pod.get("terminationGracePeriodSeconds", 30)
    pre_stop = container.get("lifecycle", {}).get("preStop", {}).get("exec", {}).get("command")
    if pre_stop and pre_stop[0] == "sleep" and len(pre_stop) == 2:
        grace -= int(pre_stop[1])
    run_server(server, plain_args, env, probes, grace)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--server", required=True, help="the incise-server binary")
    parser.add_argument("--repo", required=True, help="the repository's root")
    parser.add_argument("--kubectl", default="kubectl", help="a kubectl with kustomize")
    options = parser.parse_args()
    try:
        docs = render(options.kubectl, os.path.join(options.repo, "deploy", "kubernetes"))
        check_all(docs, options.repo, options.server)
    except Fatal as e:
        check(False, str(e))
    if failures:
        print(f"kubernetes_manifests_test: {len(failures)} failure(s)", file=sys.stderr)
        return 1
    print("kubernetes_manifests_test: the manifests agree with the server")
    return 0


if __name__ == "__main__":
    sys.exit(main())
