#!/usr/bin/env bash
# A single-node SLURM with accounting on this machine, for trying and testing profiles/slurm.
#
#   scripts/slurm_local.sh start    install (apt, first time only) and start; idempotent
#   scripts/slurm_local.sh stop     stop what it started; remove the PID files and slurm.conf
#   scripts/slurm_local.sh status   daemons and partitions
#
# Needs root and apt (Debian 12: slurm-wlm 22.05, slurmdbd, MariaDB, MUNGE). There is no systemd
# here, so the daemons are started by hand. The node is this machine (all its CPUs, 90 % of its
# memory), in two partitions: `batch` (the default) and QSM_SLURM_PARTITION (default `debug`).
# The cluster QSM_SLURM_CLUSTER (default `qsm`) keeps accounts in slurmdbd (MariaDB), so sacct
# works and jobs need a valid account: root (and $SUDO_USER, if set) may use QSM_SLURM_ACCOUNT
# (default `qsm`); root's default account stays `root`. `start` ends when the node is idle and
# prints `account=... partition=...`: what to give the profile (SBATCH_ACCOUNT, SBATCH_PARTITION).
set -euo pipefail

CLUSTER=${QSM_SLURM_CLUSTER:-qsm}
ACCOUNT=${QSM_SLURM_ACCOUNT:-qsm}
PARTITION=${QSM_SLURM_PARTITION:-debug}
DB_PASS=${QSM_SLURM_DB_PASS:-qsm-slurmdbd}
PACKAGES=(slurm-wlm slurmdbd mariadb-server munge)
ETC=/etc/slurm
RUN=/run/slurm
LOG=/var/log/slurm
NODE=$(hostname -s)

say() { echo "slurm_local: $*" >&2; }
die() {
    say "error: $*"
    exit 1
}

# wait_for SECONDS WHAT COMMAND...: retry COMMAND every 0.2 s until it succeeds
wait_for() {
    local limit=$1 what=$2
    shift 2
    local deadline=$((SECONDS + limit))
    until "$@" >/dev/null 2>&1; do
        ((SECONDS < deadline)) || die "$what not ready after ${limit} s"
        sleep 0.2
    done
}

# pid_alive PIDFILE: the PID file names a running process (a stale file is removed)
pid_alive() {
    local pid
    [[ -s $1 ]] || return 1
    pid=$(<"$1")
    if kill -0 "$pid" 2>/dev/null; then
        return 0
    fi
    rm -f "$1"
    return 1
}

install_packages() {
    local missing=()
    command -v sbatch >/dev/null || missing+=(slurm-wlm)
    command -v slurmdbd >/dev/null || missing+=(slurmdbd)
    command -v mariadbd >/dev/null || missing+=(mariadb-server)
    command -v munged >/dev/null || missing+=(munge)
    ((${#missing[@]} == 0)) && return 0
    command -v apt-get >/dev/null || die "apt-get not found: install ${PACKAGES[*]} yourself"
    say "installing ${missing[*]} (apt)"
    local apt=(apt-get -o DPkg::Lock::Timeout=600 -y -q --no-install-recommends)
    if ! DEBIAN_FRONTEND=noninteractive "${apt[@]}" install "${missing[@]}" >/dev/null; then
        apt-get -o DPkg::Lock::Timeout=600 -q update >/dev/null
        DEBIAN_FRONTEND=noninteractive "${apt[@]}" install "${missing[@]}" >/dev/null
    fi
}

start_munge() {
    if [[ ! -s /etc/munge/munge.key ]]; then
        mungekey --create --keyfile=/etc/munge/munge.key
    fi
    chown munge:munge /etc/munge/munge.key
    chmod 400 /etc/munge/munge.key
    install -d -o munge -g munge -m 755 /run/munge
    if ! pid_alive /run/munge/munged.pid; then
        rm -f /run/munge/munge.socket.2*
        runuser -u munge -- /usr/sbin/munged
    fi
    wait_for 10 munge bash -c 'munge -n | unmunge'
}

start_mariadb() {
    install -d -o mysql -g mysql -m 755 /run/mysqld
    install -d -o mysql -g adm -m 2750 /var/log/mysql
    if [[ ! -d /var/lib/mysql/mysql ]]; then
        mariadb-install-db --user=mysql --datadir=/var/lib/mysql >/dev/null
    fi
    if ! mariadb-admin ping >/dev/null 2>&1; then
        rm -f /run/mysqld/mysqld.pid
        setsid /usr/sbin/mariadbd --user=mysql --bind-address=127.0.0.1 \
            --pid-file=/run/mysqld/mysqld.pid >>/var/log/mysql/qsm_slurm.log 2>&1 </dev/null &
    fi
    wait_for 30 MariaDB mariadb-admin ping
    mariadb -e "CREATE USER IF NOT EXISTS 'slurm'@'localhost' IDENTIFIED BY '$DB_PASS';
        GRANT ALL ON slurm_acct_db.* TO 'slurm'@'localhost'; FLUSH PRIVILEGES;"
}

# write_if_changed FILE MODE OWNER: write stdin to FILE; return 0 if its content changed
write_if_changed() {
    local tmp
    tmp=$(mktemp)
    cat >"$tmp"
    if [[ -f $1 ]] && cmp -s "$tmp" "$1"; then
        rm -f "$tmp"
        return 1
    fi
    install -m "$2" -o "$3" -g "$3" "$tmp" "$1"
    rm -f "$tmp"
}

write_configs() {
    local node_line cpus mem changed=1
    install -d -o slurm -g slurm -m 755 "$RUN" "$LOG" /var/lib/slurm/slurmctld
    install -d -m 755 /var/lib/slurm/slurmd "$ETC"
    # the node as slurmd sees it: CPUs, sockets, cores, threads; memory at 90 %
    node_line=$(slurmd -C | head -1)
    cpus=$(grep -o 'CPUs=[0-9]*' <<<"$node_line")
    mem=$(grep -o 'RealMemory=[0-9]*' <<<"$node_line" | cut -d= -f2)
    node_line=$(sed -E "s/^NodeName=[^ ]+/NodeName=$NODE NodeAddr=127.0.0.1/; \
        s/RealMemory=[0-9]+/RealMemory=$((mem * 9 / 10))/" <<<"$node_line")
    write_if_changed "$ETC/slurmdbd.conf" 600 slurm <<EOF && changed=0
# written by scripts/slurm_local.sh
AuthType=auth/munge
DbdHost=localhost
SlurmUser=slurm
PidFile=$RUN/slurmdbd.pid
LogFile=$LOG/slurmdbd.log
StorageType=accounting_storage/mysql
StorageHost=localhost
StorageUser=slurm
StoragePass=$DB_PASS
StorageLoc=slurm_acct_db
EOF
    write_if_changed "$ETC/slurm.conf" 644 root <<EOF && changed=0
# written by scripts/slurm_local.sh: one node ($cpus), partition $PARTITION, accounting through
# slurmdbd (sacct works; jobs need an account). No cgroups here: linuxproc and task/none.
ClusterName=$CLUSTER
SlurmctldHost=$NODE(127.0.0.1)
SlurmUser=slurm
AuthType=auth/munge
StateSaveLocation=/var/lib/slurm/slurmctld
SlurmdSpoolDir=/var/lib/slurm/slurmd
SlurmctldPidFile=$RUN/slurmctld.pid
SlurmdPidFile=$RUN/slurmd.pid
SlurmctldLogFile=$LOG/slurmctld.log
SlurmdLogFile=$LOG/slurmd.log
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SchedulerType=sched/backfill
MpiDefault=none
ReturnToService=2
MinJobAge=300
AccountingStorageType=accounting_storage/slurmdbd
AccountingStorageHost=localhost
AccountingStorageEnforce=associations
JobAcctGatherType=jobacct_gather/linux
JobAcctGatherFrequency=30
$node_line State=UNKNOWN
PartitionName=batch Nodes=$NODE Default=YES MaxTime=INFINITE State=UP
PartitionName=$PARTITION Nodes=$NODE Default=NO MaxTime=INFINITE State=UP
EOF
    return $changed
}

start_slurm() {
    local configs_changed=1
    write_configs && configs_changed=0
    if ((configs_changed == 0)); then
        stop_slurm_daemons # a new configuration: restart what runs
    fi
    if ! pid_alive "$RUN/slurmdbd.pid"; then
        slurmdbd
    fi
    wait_for 30 slurmdbd sacctmgr -n list cluster
    if [[ -z $(sacctmgr -n -P list cluster "$CLUSTER" format=cluster) ]]; then
        sacctmgr -i add cluster "$CLUSTER" >/dev/null
    fi
    if [[ -z $(sacctmgr -n -P list account "$ACCOUNT" format=account) ]]; then
        sacctmgr -i add account "$ACCOUNT" cluster="$CLUSTER" \
            description="qsm-design tests" organization=qsm >/dev/null
    fi
    local user
    for user in root ${SUDO_USER:-}; do
        if [[ -z $(sacctmgr -n -P list assoc user="$user" account="$ACCOUNT" format=user) ]]; then
            sacctmgr -i add user "$user" account="$ACCOUNT" cluster="$CLUSTER" >/dev/null
        fi
    done
    if ! pid_alive "$RUN/slurmctld.pid"; then
        slurmctld
    fi
    wait_for 30 slurmctld scontrol ping
    if ! pid_alive "$RUN/slurmd.pid"; then
        slurmd
    fi
    # idle (or already running jobs): not down, drained or unknown
    wait_for 60 "node $NODE" bash -c "sinfo -h -n $NODE -o %t | grep -qxE 'idle|mix|alloc'"
    say "up: node $NODE idle; partition $PARTITION, account $ACCOUNT (cluster $CLUSTER)"
    echo "account=$ACCOUNT partition=$PARTITION"
}

# stop_daemon NAME PIDFILE: SIGTERM, wait up to 15 s, then SIGKILL; remove the PID file
stop_daemon() {
    local pid deadline
    if pid_alive "$2"; then
        pid=$(<"$2")
        kill "$pid" 2>/dev/null || true
        deadline=$((SECONDS + 15))
        while kill -0 "$pid" 2>/dev/null; do
            if ((SECONDS >= deadline)); then
                say "$1 ignored SIGTERM: SIGKILL"
                kill -9 "$pid" 2>/dev/null || true
            fi
            sleep 0.2
        done
    fi
    rm -f "$2"
}

stop_slurm_daemons() {
    stop_daemon slurmd "$RUN/slurmd.pid"
    stop_daemon slurmctld "$RUN/slurmctld.pid"
    stop_daemon slurmdbd "$RUN/slurmdbd.pid"
}

stop_all() {
    if command -v scancel >/dev/null && scontrol ping >/dev/null 2>&1; then
        scancel --full --user=root 2>/dev/null || true
    fi
    stop_slurm_daemons
    if command -v mariadb-admin >/dev/null && mariadb-admin ping >/dev/null 2>&1; then
        mariadb-admin shutdown
    fi
    rm -f /run/mysqld/mysqld.pid
    stop_daemon munged /run/munge/munged.pid
    # Without a controller, every SLURM client command retries for MessageTimeout (10 s), and the
    # executor plugin runs `scontrol show config` whenever Snakemake starts, SLURM or not: 9 s
    # added to every run on this machine. Without slurm.conf they fail at once; `start` writes it.
    rm -f "$ETC/slurm.conf"
    say "stopped"
}

status() {
    local name file
    for name in munged:/run/munge/munged.pid slurmdbd:$RUN/slurmdbd.pid \
        slurmctld:$RUN/slurmctld.pid slurmd:$RUN/slurmd.pid; do
        file=${name#*:}
        if pid_alive "$file"; then
            echo "${name%%:*}: running ($(<"$file"))"
        else
            echo "${name%%:*}: stopped"
        fi
    done
    if mariadb-admin ping >/dev/null 2>&1; then echo "mariadb: running"; else echo "mariadb: stopped"; fi
    sinfo 2>/dev/null || true
}

[[ $(id -u) == 0 ]] || die "must run as root (it installs packages and starts daemons)"
case ${1:-} in
start)
    install_packages
    start_munge
    start_mariadb
    start_slurm
    ;;
stop) stop_all ;;
status) status ;;
*)
    echo "usage: $0 start|stop|status" >&2
    exit 2
    ;;
esac
