#!/usr/bin/env python3
"""Static instruction counts of a SPIR-V module (BENCHMARKS.md, issue 14): every instruction in
function bodies, ALU (arithmetic, comparisons, conversions, extended instructions, shuffles)
and texture ops (image samples and LOD queries), in total and per function. Needs spirv-dis
(Debian: spirv-tools). Usage: docs/tools/spirv_count.py MODULE.spv..."""
import re,subprocess,sys
def count(path):
    dis=subprocess.run(['spirv-dis','--raw-id',path],capture_output=True,text=True).stdout.splitlines()
    total=alu=tex=0; funcs={}; cur=None
    alu_re=re.compile(r'Op(F|I|S|U)(Add|Sub|Mul|Div|Negate|Mod|Rem)|OpExtInst|OpDot|OpVectorTimes|OpMatrixTimes|OpSelect|OpF(Ord|Unord)|OpConvert|OpBitcast|OpLogical|OpVectorShuffle|OpCompositeConstruct|OpCompositeExtract|OpDPd|OpFwidth')
    for l in dis:
        m=re.search(r'(Op\w+)',l)
        if not m: continue
        op=m.group(1)
        if op=='OpFunction': cur=l.split('=')[0].strip(); funcs[cur]=[0,0,0]; continue
        if cur is None: continue
        if op in('OpFunctionEnd',): cur=None; continue
        if op in ('OpLabel','OpFunctionParameter','OpVariable'): continue
        funcs[cur][0]+=1; total+=1
        if op.startswith('OpImageSample') or op.startswith('OpImageQueryLod'): funcs[cur][2]+=1; tex+=1
        elif alu_re.match(op): funcs[cur][1]+=1; alu+=1
    return total,alu,tex,funcs
for p in sys.argv[1:]:
    t,a,x,f=count(p); print(p, 'instructions',t,'ALU',a,'texture ops',x, 'functions',len(f))
