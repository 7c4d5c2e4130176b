program bench_jfo
end program
